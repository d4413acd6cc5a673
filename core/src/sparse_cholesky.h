#pragma once
// Private to kc::core: the sparse SPD factorization every kernel-sized system uses.

#include <Eigen/CholmodSupport>

#include "kc/core/kernel/kernel_matrix.h"

namespace kc::detail {

/// CHOLMOD's supernodal Cholesky (SuiteSparse). Kernel matrices have dense cut-off
/// neighbourhoods that form large supernodes, so this runs on BLAS-3 kernels and is several times
/// faster than a simplicial factorization. pivotRatio() is (min Lᵢᵢ / max Lᵢᵢ)² of K = LLᵀ, the
/// ratio of the smallest to the largest pivot, for detecting near-singular systems.
class SupernodalCholesky : public Eigen::CholmodSupernodalLLT<SparseMatrix> {
 public:
  double pivotRatio() { return m_cholmodFactor ? cholmod_rcond(m_cholmodFactor, &cholmod()) : 0.0; }
};

}  // namespace kc::detail
