#pragma once
// Private to kc::core: the sparse SPD factorizations every kernel-sized system uses.

#include <Eigen/CholmodSupport>
#include <memory>
#include <vector>

#include "blas_threads.h"
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
    serialBlas();
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

/// The same supernodal factorization P A Pᵀ = L Lᵀ (CHOLMOD's fill-reducing order P, the same L
/// and the same solves to the bit) in less memory, for the largest systems (the kernel matrix, the
/// initial weights' diffusion): compute() takes A, finds P on its pattern, keeps only
/// tril(P A Pᵀ) — A is released before the factor is allocated — and factors that in its natural
/// order, which CHOLMOD does in place instead of through two permuted copies; tril(P A Pᵀ) is
/// released after. Peak: L + half of A, against L + A + two halves of A.
class PermutedCholesky {
 public:
  PermutedCholesky();
  ~PermutedCholesky();
  PermutedCholesky(const PermutedCholesky&) = delete;
  PermutedCholesky& operator=(const PermutedCholesky&) = delete;

  /// Factorizes the symmetric positive definite A (n×n; its lower triangle is read, so full or
  /// lower storage both do). A is consumed: empty on return.
  void compute(SparseMatrix&& A);
  /// The last compute() succeeded: solve() and pivotRatio() can run.
  bool ok() const { return m_ok; }
  /// The last compute() failed because CHOLMOD could not allocate its analysis or factor.
  bool outOfMemory() const { return m_outOfMemory; }
  /// (min Lᵢᵢ / max Lᵢᵢ)², CHOLMOD's reciprocal condition estimate; 0 without a factor.
  double pivotRatio() const;
  /// A⁻¹B (n×k). Requires ok(); a failed CHOLMOD solve gives a matrix of NaN.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  /// Frees the factor (ok() becomes false).
  void release();

 private:
  struct Cholmod;
  std::unique_ptr<Cholmod> m_cholmod;  // the CHOLMOD workspace and factor
  std::vector<int> m_order;            // row k of P A Pᵀ is row m_order[k] of A
  bool m_ok = false, m_outOfMemory = false;
};

}  // namespace kc::detail
