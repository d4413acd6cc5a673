#include "row_block_cholesky.h"

#include <algorithm>
#include <cstring>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include "kc/core/parallel.h"
#include "../weights/simd2.h"
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
    store2(y + c, load2(y + c) - l * load2(x + c));
    c += 2;
  }
  for (; c < W; ++c) y[c] -= l * x[c];
}

/// One block of columns of B ← A⁻¹ B: the factor (perm, start, row, value), the row-major n×k B,
/// the block's first column c0, and y, room for the block (n rows of its width).
struct Block {
  const std::vector<int>& perm;
  const std::vector<int>& start;
  const std::vector<int>& row;
  const std::vector<double>& value;
  double* b;
  Index n, k, c0;
  double* y;
};

/// Columns c0 … c0 + W − 1: the block gathered into y (rows in the permuted order), the two
/// triangular solves, the block scattered back. W is a compile-time width so the row operations
/// are short fixed-length loops the compiler unrolls; always inlined into solveBlock's clones.
template <int W>
[[gnu::always_inline]] inline void solveBlockOf(const Block& q) {
  const auto &perm = q.perm, &start = q.start, &row = q.row;
  const auto& value = q.value;
  double* y = q.y;
  for (Index i = 0; i < q.n; ++i) std::memcpy(y + Index(perm[std::size_t(i)]) * W, q.b + i * q.k + q.c0, W * sizeof(double));
  // L y = P b: column j divides y_j by L_jj, then subtracts L_ij y_j from the rows below.
  for (Index j = 0; j < q.n; ++j) {
    double* yj = y + j * W;
    const int s0 = start[std::size_t(j)], s1 = start[std::size_t(j + 1)];
    const double d = value[std::size_t(s0)];
    for (int c = 0; c < W; ++c) yj[c] /= d;
    for (int s = s0 + 1; s < s1; ++s) subtractScaled<W>(y + Index(row[std::size_t(s)]) * W, yj, value[std::size_t(s)]);
  }
  // Lᵀ x = y: x_j = (y_j − Σ_{i>j} L_ij x_i) / L_jj, from the last row up.
  for (Index j = q.n - 1; j >= 0; --j) {
    double* yj = y + j * W;
    const int s0 = start[std::size_t(j)], s1 = start[std::size_t(j + 1)];
    for (int s = s0 + 1; s < s1; ++s) subtractScaled<W>(yj, y + Index(row[std::size_t(s)]) * W, value[std::size_t(s)]);
    const double d = value[std::size_t(s0)];
    for (int c = 0; c < W; ++c) yj[c] /= d;
  }
  for (Index i = 0; i < q.n; ++i) std::memcpy(q.b + i * q.k + q.c0, y + Index(perm[std::size_t(i)]) * W, W * sizeof(double));
}

/// solveBlockOf for the width w (1 … RowBlockCholesky::kBlock). A plain function, so that it can
/// have clones (compilers do not clone templates).
KC_VECTOR_CLONES void solveBlock(Index w, const Block& q) {
  static_assert(RowBlockCholesky::kBlock == 16);
  switch (w) {
    case 1:
      return solveBlockOf<1>(q);
    case 2:
      return solveBlockOf<2>(q);
    case 3:
      return solveBlockOf<3>(q);
    case 4:
      return solveBlockOf<4>(q);
    case 5:
      return solveBlockOf<5>(q);
    case 6:
      return solveBlockOf<6>(q);
    case 7:
      return solveBlockOf<7>(q);
    case 8:
      return solveBlockOf<8>(q);
    case 9:
      return solveBlockOf<9>(q);
    case 10:
      return solveBlockOf<10>(q);
    case 11:
      return solveBlockOf<11>(q);
    case 12:
      return solveBlockOf<12>(q);
    case 13:
      return solveBlockOf<13>(q);
    case 14:
      return solveBlockOf<14>(q);
    case 15:
      return solveBlockOf<15>(q);
    case 16:
      return solveBlockOf<16>(q);
    default:
      return;
  }
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
  parallelFor(
      blocks,
      [&](Index b) {
        const Index c0 = b * width, w = std::min(width, k - c0);
        if (w <= 0) return;
        std::vector<double> y(std::size_t(n * w));  // the block in the permuted order, row-major
        solveBlock(w, Block{m_perm, m_start, m_row, m_value, B.data(), n, k, c0, y.data()});
      },
      parallel ? 1 : blocks);
}

}  // namespace kc::detail
