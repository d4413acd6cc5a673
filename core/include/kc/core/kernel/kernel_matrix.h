#pragma once
/// Sparse kernel matrices assembled through a uniform grid: O(n · neighbours), never all pairs.

#include <Eigen/SparseCore>

#include "kc/core/kernel/gaussian_kernel.h"
#include "kc/core/types.h"

namespace kc {

using SparseMatrix = Eigen::SparseMatrix<double>;                   ///< column-major
using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// K #S×#S, K_ij = k(x_i, x_j) for |x_i − x_j| ≤ θ (thesis 3.32, 6.1); with a variable width the
/// Gibbs kernel's non-zero entries (GaussianKernel). Symmetric, full storage.
SparseMatrix assembleKernelMatrix(const Points& X, const GaussianKernel& kernel);

/// k(p)ᵀ for every query point: #P×#S, row p holds k(p, x_j) for |p − x_j| ≤ θ (3.32). `widths`:
/// the variable-width kernel's σ(x_j) (#S, GaussianKernel::widthsAt(X)) when the caller keeps them;
/// null: computed here.
SparseRowMatrix kernelRows(const Points& X, const Points& P, const GaussianKernel& kernel,
                           const Eigen::VectorXd* widths = nullptr);

/// ∂/∂p_x and ∂/∂p_y of kernelRows(X, P, kernel) (3.41–3.43; for a variable width the Gibbs
/// kernel's gradient, GaussianKernel::gradientFactor): two #P×#S matrices with its sparsity.
void kernelGradientRows(const Points& X, const Points& P, const GaussianKernel& kernel, SparseRowMatrix& Gx, SparseRowMatrix& Gy,
                        const Eigen::VectorXd* widths = nullptr);

}  // namespace kc
