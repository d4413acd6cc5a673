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
  /// Analysis and factorization of K. Unlike Eigen's compute(), a failed analysis (CHOLMOD out
  /// of memory) leaves info() != Success and outOfMemory() true instead of dereferencing a null
  /// factor; CHOLMOD prints nothing (failures are reported, STYLE.md "Errors").
  SupernodalCholesky& compute(const SparseMatrix& K) {
    cholmod().print = 0;
    m_outOfMemory = false;
    analyzePattern(K);
    if (!m_cholmodFactor || cholmod().status == CHOLMOD_OUT_OF_MEMORY) {
      m_outOfMemory = true;
      m_info = Eigen::NumericalIssue;
      m_factorizationIsOk = false;
      return *this;
    }
    factorize(K);
    if (cholmod().status == CHOLMOD_OUT_OF_MEMORY) {
      m_outOfMemory = true;
      m_info = Eigen::NumericalIssue;
    }
    return *this;
  }
  /// The last compute() failed because CHOLMOD could not allocate its factor.
  bool outOfMemory() const { return m_outOfMemory; }

  double pivotRatio() { return m_cholmodFactor ? cholmod_rcond(m_cholmodFactor, &cholmod()) : 0.0; }

 private:
  bool m_outOfMemory = false;
};

}  // namespace kc::detail
