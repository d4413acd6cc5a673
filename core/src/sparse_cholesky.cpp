#include "sparse_cholesky.h"

#include <algorithm>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <limits>
#include <utility>

namespace kc::detail {
namespace {

/// CHOLMOD's view of the lower triangle of A (stype −1: entries above the diagonal are ignored).
cholmod_sparse lowerView(SparseMatrix& A) {
  cholmod_sparse v{};
  v.nrow = static_cast<std::size_t>(A.rows());
  v.ncol = static_cast<std::size_t>(A.cols());
  v.nzmax = static_cast<std::size_t>(A.nonZeros());
  v.p = A.outerIndexPtr();
  v.i = A.innerIndexPtr();
  v.x = A.valuePtr();
  v.stype = -1;
  v.itype = CHOLMOD_INT;
  v.xtype = CHOLMOD_REAL;
  v.dtype = CHOLMOD_DOUBLE;
  v.sorted = 1;
  v.packed = 1;
  return v;
}

/// tril(P A Pᵀ) in compressed columns with sorted rows, from the lower triangle of A (compressed);
/// row k of P A Pᵀ is row order[k] of A.
SparseMatrix permutedLower(const SparseMatrix& A, const std::vector<int>& order) {
  const Index n = A.rows();
  std::vector<int> position(static_cast<std::size_t>(n));
  for (Index k = 0; k < n; ++k) position[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = static_cast<int>(k);
  // A(i, j), i ≥ j, lands at (max(a, b), min(a, b)) with a = position[i], b = position[j].
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0);
  for (Index j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (it.row() >= j) ++start[static_cast<std::size_t>(std::min(position[std::size_t(it.row())], position[std::size_t(j)])) + 1];
  for (Index c = 0; c < n; ++c) start[std::size_t(c) + 1] += start[std::size_t(c)];
  SparseMatrix L(n, n);
  L.resizeNonZeros(start.back());
  std::copy(start.begin(), start.end(), L.outerIndexPtr());
  int* row = L.innerIndexPtr();
  double* value = L.valuePtr();
  std::vector<int> next(start.begin(), start.end() - 1);
  for (Index j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
      if (it.row() < j) continue;
      const int a = position[std::size_t(it.row())], b = position[std::size_t(j)];
      const int k = next[std::size_t(std::min(a, b))]++;
      row[k] = std::max(a, b);
      value[k] = it.value();
    }
  std::vector<std::pair<int, double>> column;
  for (Index c = 0; c < n; ++c) {
    const int begin = start[std::size_t(c)], end = start[std::size_t(c) + 1];
    column.clear();
    for (int k = begin; k < end; ++k) column.emplace_back(row[k], value[k]);
    std::sort(column.begin(), column.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (int k = begin; k < end; ++k) std::tie(row[k], value[k]) = column[std::size_t(k - begin)];
  }
  return L;
}

/// Gives the heap's free pages back to the system (glibc keeps freed blocks below its mmap
/// threshold, which grows up to 32 MB, in its arenas), so that the factor about to be allocated
/// (mapped anew) adds to what is in use rather than to what was in use before.
void returnFreeMemory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace

struct PermutedCholesky::Cholmod {
  cholmod_common common;
  cholmod_factor* L = nullptr;
  Cholmod() {
    cholmod_start(&common);
    common.print = 0;  // failures are reported, STYLE.md "Errors"
  }
  ~Cholmod() {
    cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
  }
};

PermutedCholesky::PermutedCholesky() : m_cholmod(std::make_unique<Cholmod>()) {}
PermutedCholesky::~PermutedCholesky() = default;

void PermutedCholesky::release() {
  cholmod_free_factor(&m_cholmod->L, &m_cholmod->common);
  m_order.clear();
  m_ok = false;
}

void PermutedCholesky::compute(SparseMatrix&& A) {
  serialBlas();
  release();
  m_outOfMemory = false;
  cholmod_common& c = m_cholmod->common;
  A.makeCompressed();
  const Index n = A.rows();
  {
    // P: CHOLMOD's default choice (AMD, or METIS when AMD leaves much fill), postordered; the
    // simplicial analysis is enough for the order.
    c.nmethods = 0;
    c.postorder = 1;
    c.supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_sparse view = lowerView(A);
    cholmod_factor* order = cholmod_analyze(&view, &c);
    if (!order || c.status == CHOLMOD_OUT_OF_MEMORY) {
      m_outOfMemory = true;
      cholmod_free_factor(&order, &c);
      return;
    }
    const int* perm = static_cast<const int*>(order->Perm);
    m_order.assign(perm, perm + n);
    cholmod_free_factor(&order, &c);
  }
  SparseMatrix B = permutedLower(A, m_order);
  SparseMatrix().swap(A);
  returnFreeMemory();
  // tril(P A Pᵀ) in its natural order, not postordered again (P already is): CHOLMOD factors it
  // without copying it, into the supernodes the analysis of A with P would give.
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_NATURAL;
  c.postorder = 0;
  c.supernodal = CHOLMOD_SUPERNODAL;
  cholmod_sparse view = lowerView(B);
  cholmod_factor*& L = m_cholmod->L;
  L = cholmod_analyze(&view, &c);
  m_outOfMemory = !L || c.status == CHOLMOD_OUT_OF_MEMORY;
  if (!m_outOfMemory) {
    cholmod_factorize(&view, L, &c);
    m_outOfMemory = c.status == CHOLMOD_OUT_OF_MEMORY;
  }
  // Positive definite when the factorization reached the last column (a tiny pivot is only a
  // warning; pivotRatio() judges it).
  m_ok = !m_outOfMemory && c.status >= CHOLMOD_OK && L->minor == L->n;
  c.nmethods = 0;
  c.postorder = 1;
  if (!m_ok) release();
}

double PermutedCholesky::pivotRatio() const {
  return m_cholmod->L ? cholmod_rcond(m_cholmod->L, &m_cholmod->common) : 0.0;
}

Eigen::MatrixXd PermutedCholesky::solve(const Eigen::MatrixXd& B) const {
  const Index n = B.rows(), k = B.cols();
  Eigen::MatrixXd X(n, k);
  if (!m_ok || n != Index(m_order.size())) {
    X.setConstant(std::numeric_limits<double>::quiet_NaN());
    return X;
  }
  if (k == 0) return X;
  Eigen::MatrixXd Y(n, k);
  for (Index r = 0; r < n; ++r) Y.row(r) = B.row(m_order[std::size_t(r)]);
  cholmod_dense y{};
  y.nrow = static_cast<std::size_t>(n);
  y.ncol = static_cast<std::size_t>(k);
  y.nzmax = y.nrow * y.ncol;
  y.d = y.nrow;
  y.x = Y.data();
  y.xtype = CHOLMOD_REAL;
  y.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, m_cholmod->L, &y, &m_cholmod->common);
  if (!x) {
    X.setConstant(std::numeric_limits<double>::quiet_NaN());
    return X;
  }
  const Eigen::Map<const Eigen::MatrixXd> solved(static_cast<const double*>(x->x), n, k);
  for (Index r = 0; r < n; ++r) X.row(m_order[std::size_t(r)]) = solved.row(r);
  cholmod_free_dense(&x, &m_cholmod->common);
  return X;
}

}  // namespace kc::detail
