#include "kc/core/field/field.h"

#include <stdexcept>
#include <string>

#include "kc/core/parallel.h"

namespace kc {

namespace detail {
std::vector<Index> fieldColumns(std::span<const Index> columns, Index m) {
  std::vector<Index> out;
  if (columns.empty()) {
    out.resize(static_cast<std::size_t>(m));
    for (Index k = 0; k < m; ++k) out[static_cast<std::size_t>(k)] = k;
    return out;
  }
  for (const Index c : columns) {
    if (c < 0 || c >= m) throw std::invalid_argument("field: column " + std::to_string(c) + " out of range 0.." + std::to_string(m - 1));
    out.push_back(c);
  }
  return out;
}
}  // namespace detail

void CoordinateField::apply(const SparseRowMatrix& E, std::span<const Index> columns, Weights& W) const {
  const Index m = controls();
  if (E.cols() != nodes())
    throw std::invalid_argument("field: the operator has " + std::to_string(E.cols()) + " columns but the field has " +
                                std::to_string(nodes()) + " nodes");
  if (W.rows() != E.rows() || W.cols() != m) throw std::invalid_argument("field: W must be #P×m");
  const std::vector<Index> cols = detail::fieldColumns(columns, m);
  const RowMatrix C = coefficientColumns(cols);
  const Index c = static_cast<Index>(cols.size());
  // Each point writes only its own row: identical results for any thread count.
  parallelFor(E.rows(), [&](Index p) {
    Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(c);
    for (SparseRowMatrix::InnerIterator it(E, p); it; ++it) row.noalias() += it.value() * C.row(it.col());
    for (Index k = 0; k < c; ++k) W(p, cols[static_cast<std::size_t>(k)]) = row(k);
  }, 256);
}

Weights CoordinateField::weightsAt(const Points& P) const {
  Weights W(P.rows(), controls());
  apply(evaluationOperator(P), {}, W);
  if (m_bound) m_bound->apply(P, W);
  return W;
}

void CoordinateField::gradientsAt(const Points& P, Weights& dWdx, Weights& dWdy) const {
  SparseRowMatrix Ex, Ey;
  gradientOperators(P, Ex, Ey);
  dWdx.resize(P.rows(), controls());
  dWdy.resize(P.rows(), controls());
  apply(Ex, {}, dWdx);
  apply(Ey, {}, dWdy);
  boundGradients(P, dWdx, dWdy, [&](const Points& Q) {
    Weights W(Q.rows(), controls());
    apply(evaluationOperator(Q), {}, W);
    return W;
  });
}

}  // namespace kc
