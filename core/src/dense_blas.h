#pragma once
// Private to kc::core: the system's BLAS and LAPACK (the library CHOLMOD's supernodal factorization
// already uses, e.g. OpenBLAS, which picks kernels for the CPU it runs on) for the dense
// factorizations and solves of a few hundred to a few thousand rows: Eigen's own blocked code is
// compiled for the baseline instruction set here and is slower at these sizes. Column-major
// matrices, lower triangles; sizes must fit BLAS's 32-bit integers.

#include <Eigen/Dense>

namespace kc::blas {

/// A = L Lᵀ in place (LAPACK dpotrf; the lower triangle is read and overwritten by L, the upper one
/// is not touched). False when a pivot is not positive.
bool cholesky(Eigen::Ref<Eigen::MatrixXd> A);

/// B ← L⁻¹ B, or L⁻ᵀ B with `transpose` (dtrsm from the left; L lower triangular, the lower triangle
/// of `L` is read).
void solveLower(const Eigen::Ref<const Eigen::MatrixXd>& L, Eigen::Ref<Eigen::MatrixXd> B, bool transpose = false);

/// B ← B L⁻ᵀ (dtrsm from the right).
void solveLowerTransposeRight(const Eigen::Ref<const Eigen::MatrixXd>& L, Eigen::Ref<Eigen::MatrixXd> B);

/// C ← β C + α A Aᵀ, or β C + α Aᵀ A with `transposeA`, on C's lower triangle only (dsyrk).
void rankUpdateLower(Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& A, double alpha, double beta,
                     bool transposeA = false);

/// C ← β C + α op(A) op(B), op = transpose where asked (dgemm).
void multiply(Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& A, bool transposeA,
              const Eigen::Ref<const Eigen::MatrixXd>& B, bool transposeB, double alpha = 1.0, double beta = 0.0);

}  // namespace kc::blas
