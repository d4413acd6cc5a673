#include "row_block_cholesky.h"

#include <algorithm>
#include <utility>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include "kc/core/parallel.h"

namespace kc::detail {

bool RowBlockCholesky::compute(const SparseMatrix& A) {
  m_ok = false;
  Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> llt(A);
  if (llt.info() != Eigen::Success) return false;
  const Index n = A.rows();
  // Eigen solves P A Pᵀ = L Lᵀ with (P b)(p(i)) = b(i).
  const auto& p = llt.permutationP().indices();
  m_perm.assign(std::size_t(n), 0);
  for (Index i = 0; i < n; ++i) m_perm[std::size_t(i)] = p(i);
  const auto& L = llt.matrixL().nestedExpression();  // column-major, lower, diagonal first
  m_start.assign(L.outerIndexPtr(), L.outerIndexPtr() + n + 1);
  m_row.assign(L.innerIndexPtr(), L.innerIndexPtr() + L.nonZeros());
  m_value.assign(L.valuePtr(), L.valuePtr() + L.nonZeros());
  for (Index j = 0; j < n; ++j) {
    const int first = m_start[std::size_t(j)];
    if (first >= m_start[std::size_t(j + 1)] || m_row[std::size_t(first)] != j || !(m_value[std::size_t(first)] > 0.0))
      return false;
  }
  m_ok = true;
  return true;
}

namespace {

/// The two triangular solves on one block y (n rows of W values, row-major, permuted order); W
/// a compile-time width so the row updates are short fixed-length loops the compiler unrolls.
template <int W>
void solveBlock(const std::vector<int>& start, const std::vector<int>& row, const std::vector<double>& value,
                Index n, double* y) {
  // L y = P b: column j divides y_j by L_jj, then subtracts L_ij y_j from the rows below.
  for (Index j = 0; j < n; ++j) {
    double* yj = y + j * W;
    const int s0 = start[std::size_t(j)], s1 = start[std::size_t(j + 1)];
    const double d = value[std::size_t(s0)];
    for (int c = 0; c < W; ++c) yj[c] /= d;
    for (int s = s0 + 1; s < s1; ++s) {
      double* yi = y + Index(row[std::size_t(s)]) * W;
      const double l = value[std::size_t(s)];
      for (int c = 0; c < W; ++c) yi[c] -= l * yj[c];
    }
  }
  // Lᵀ x = y: x_j = (y_j − Σ_{i>j} L_ij x_i) / L_jj, from the last row up.
  for (Index j = n - 1; j >= 0; --j) {
    double* yj = y + j * W;
    const int s0 = start[std::size_t(j)], s1 = start[std::size_t(j + 1)];
    for (int s = s0 + 1; s < s1; ++s) {
      const double* yi = y + Index(row[std::size_t(s)]) * W;
      const double l = value[std::size_t(s)];
      for (int c = 0; c < W; ++c) yj[c] -= l * yi[c];
    }
    const double d = value[std::size_t(s0)];
    for (int c = 0; c < W; ++c) yj[c] /= d;
  }
}

template <int... W>
void solveBlockOfWidth(Index w, std::integer_sequence<int, W...>, const std::vector<int>& start,
                       const std::vector<int>& row, const std::vector<double>& value, Index n, double* y) {
  ((w == W + 1 ? solveBlock<W + 1>(start, row, value, n, y) : void()), ...);
}

}  // namespace

void RowBlockCholesky::solveInPlace(RowMatrix& B, bool parallel) const {
  const Index n = size(), k = B.cols();
  if (k == 0) return;
  // Blocks of at most kBlock columns, at least two (both threads busy), as even as k allows (k
  // alone decides, not the threads). Each column gets the same operations whatever its block.
  const Index blocks = std::max(std::min(k, Index(2)), (k + kBlock - 1) / kBlock), width = (k + blocks - 1) / blocks;
  parallelFor(blocks, [&](Index b) {
    const Index c0 = b * width, w = std::min(width, k - c0);
    std::vector<double> y(std::size_t(n * w));  // the block in the permuted order, row-major
    for (Index i = 0; i < n; ++i)
      for (Index c = 0; c < w; ++c) y[std::size_t(m_perm[std::size_t(i)] * w + c)] = B(i, c0 + c);
    solveBlockOfWidth(w, std::make_integer_sequence<int, int(kBlock)>{}, m_start, m_row, m_value, n, y.data());
    for (Index i = 0; i < n; ++i)
      for (Index c = 0; c < w; ++c) B(i, c0 + c) = y[std::size_t(m_perm[std::size_t(i)] * w + c)];
  }, parallel ? 1 : blocks);
}

}  // namespace kc::detail
