#include "row_block_cholesky.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include "kc/core/parallel.h"
#include "simd.h"

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

/// y ← y − l·x for rows of W values, four at a time, then two (the compiler does not vectorize
/// the unrolled loop by itself: rows of the block may alias).
template <int W>
inline void subtractScaled(double* y, const double* x, double l) {
  int c = 0;
  for (; c + 4 <= W; c += 4) {
    D4 a, b;
    std::memcpy(&a, y + c, sizeof a);
    std::memcpy(&b, x + c, sizeof b);
    a -= l * b;
    std::memcpy(y + c, &a, sizeof a);
  }
  if constexpr (W % 4 >= 2) {
    D2 a, b;
    std::memcpy(&a, y + c, sizeof a);
    std::memcpy(&b, x + c, sizeof b);
    a -= l * b;
    std::memcpy(y + c, &a, sizeof a);
    c += 2;
  }
  for (; c < W; ++c) y[c] -= l * x[c];
}

/// Columns c0 … c0 + W − 1 of the row-major n×k B ← A⁻¹ B: the block gathered into y (n rows of
/// W values in the permuted order), the two triangular solves, the block scattered back. W is a
/// compile-time width so the row operations are short fixed-length loops the compiler unrolls.
template <int W>
KC_VECTOR_CLONES void solveBlock(const std::vector<int>& perm, const std::vector<int>& start, const std::vector<int>& row,
                                 const std::vector<double>& value, double* b, Index n, Index k, Index c0, double* y) {
  for (Index i = 0; i < n; ++i) std::memcpy(y + Index(perm[std::size_t(i)]) * W, b + i * k + c0, W * sizeof(double));
  // L y = P b: column j divides y_j by L_jj, then subtracts L_ij y_j from the rows below.
  for (Index j = 0; j < n; ++j) {
    double* yj = y + j * W;
    const int s0 = start[std::size_t(j)], s1 = start[std::size_t(j + 1)];
    const double d = value[std::size_t(s0)];
    for (int c = 0; c < W; ++c) yj[c] /= d;
    for (int s = s0 + 1; s < s1; ++s) subtractScaled<W>(y + Index(row[std::size_t(s)]) * W, yj, value[std::size_t(s)]);
  }
  // Lᵀ x = y: x_j = (y_j − Σ_{i>j} L_ij x_i) / L_jj, from the last row up.
  for (Index j = n - 1; j >= 0; --j) {
    double* yj = y + j * W;
    const int s0 = start[std::size_t(j)], s1 = start[std::size_t(j + 1)];
    for (int s = s0 + 1; s < s1; ++s) subtractScaled<W>(yj, y + Index(row[std::size_t(s)]) * W, value[std::size_t(s)]);
    const double d = value[std::size_t(s0)];
    for (int c = 0; c < W; ++c) yj[c] /= d;
  }
  for (Index i = 0; i < n; ++i) std::memcpy(b + i * k + c0, y + Index(perm[std::size_t(i)]) * W, W * sizeof(double));
}

/// solveBlock for the width w (1 … sizeof…(W)).
template <int... W>
void solveBlockOfWidth(Index w, std::integer_sequence<int, W...>, const std::vector<int>& perm, const std::vector<int>& start,
                       const std::vector<int>& row, const std::vector<double>& value, double* b, Index n, Index k, Index c0,
                       double* y) {
  ((w == W + 1 ? solveBlock<W + 1>(perm, start, row, value, b, n, k, c0, y) : void()), ...);
}

}  // namespace

void RowBlockCholesky::solveInPlace(RowMatrix& B, bool parallel) const {
  const Index n = size(), k = B.cols();
  if (k == 0) return;
  // Blocks of at most kBlock columns, an even number of them where k allows (two threads share
  // them evenly), as even in width as k allows, the width rounded up to a multiple of 4 (whole
  // vector operations; the last block takes the rest) where the blocks stay an even number. k
  // alone decides, not the threads; each column gets the same operations whatever its block.
  Index blocks = std::max(std::min(k, Index(2)), (k + kBlock - 1) / kBlock);
  if (blocks % 2 == 1 && blocks < k) ++blocks;
  Index width = (k + blocks - 1) / blocks;
  const Index rounded = std::min((width + 3) / 4 * 4, kBlock);
  if (width > 4 && ((k + rounded - 1) / rounded) % 2 == 0) width = rounded;
  parallelFor(blocks, [&](Index b) {
    const Index c0 = b * width, w = std::min(width, k - c0);
    if (w <= 0) return;
    std::vector<double> y(std::size_t(n * w));  // the block in the permuted order, row-major
    solveBlockOfWidth(w, std::make_integer_sequence<int, int(kBlock)>{}, m_perm, m_start, m_row, m_value, B.data(), n, k, c0,
                      y.data());
  }, parallel ? 1 : blocks);
}

}  // namespace kc::detail
