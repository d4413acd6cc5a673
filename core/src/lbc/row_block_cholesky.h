#pragma once
// Private to core/lbc: a sparse Cholesky factorization whose solve works on a row-major n×k
// right-hand side in fixed blocks of columns, the blocks in parallel. Each right-hand-side row is
// read and written as one short vector, so the factor is streamed once per block instead of once
// per column, and no BLAS threads or serial phase sit inside the ADMM iteration.

#include <vector>

#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc::detail {

class RowBlockCholesky {
 public:
  /// Most columns per block (fewer, wider blocks stream the factor fewer times). The blocks depend
  /// on the column count alone, so every column is computed by the same operations in the same
  /// order whatever the thread count (bit-identical results).
  static constexpr Index kBlock = 16;

  /// Factorizes the SPD matrix A (n×n) as P A Pᵀ = L Lᵀ (AMD ordering, simplicial). Returns false
  /// (and ok() stays false) if A is not positive definite.
  bool compute(const SparseMatrix& A);
  bool ok() const { return m_ok; }
  Index size() const { return Index(m_perm.size()); }
  /// Non-zeros of L (the cost of one solve is 4·nnz·k flops for k columns).
  Index factorNonZeros() const { return Index(m_value.size()); }

  /// B ← A⁻¹ B in place for a row-major n×k B (k any), columns in blocks of at most kBlock, the
  /// blocks in parallel (parallel = true) or one after another; the result is the same.
  void solveInPlace(RowMatrix& B, bool parallel = true) const;

 private:
  bool m_ok = false;
  std::vector<int> m_perm;     // row i of B is row m_perm[i] of the permuted system
  std::vector<int> m_start;    // CSC of L: column j is m_start[j]..m_start[j+1]−1, diagonal first
  std::vector<int> m_row;
  std::vector<double> m_value;
};

}  // namespace kc::detail
