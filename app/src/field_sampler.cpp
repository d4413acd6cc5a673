#include "kc/app/field_sampler.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace kc::app {

FieldSampler::FieldSampler(const CoordinateField& field, const Points& P) {
  if (!field.ready()) throw std::invalid_argument("FieldSampler: the coordinate field is not computed");
  m_E = field.evaluationOperator(P);
  m_P = P;
}

void FieldSampler::bound(const CoordinateField& field, Weights& W) {
  m_rows.clear();
  m_unbounded.resize(0, 0);
  const std::shared_ptr<const LobeBound> b = field.sharedLobeBound();
  if (!b) return;
  if (b != m_boundsOf) {  // ℓ at the points, once per bound, where needed (NaN: not yet)
    m_bounds.assign(static_cast<std::size_t>(m_P.rows()), std::numeric_limits<double>::quiet_NaN());
    m_boundsOf = b;
  }
  // The rows below their bound (only a weight below −depth can be): keep their unbounded weights,
  // then project them.
  for (Index i = 0; i < W.rows(); ++i) {
    const double least = W.row(i).minCoeff();
    if (!(least < -b->depth())) continue;
    double& l = m_bounds[static_cast<std::size_t>(i)];
    if (std::isnan(l)) l = b->bound(m_P.row(i).transpose());
    if (least < l) m_rows.push_back(i);
  }
  m_unbounded.resize(static_cast<Index>(m_rows.size()), W.cols());
  for (std::size_t k = 0; k < m_rows.size(); ++k) m_unbounded.row(static_cast<Index>(k)) = W.row(m_rows[k]);
  b->project(m_P, m_bounds, m_rows, W);
}

void FieldSampler::updateColumns(const CoordinateField& field, std::span<const Index> columns, Weights& W) {
  if (columns.empty()) return;
  // The bounded rows get their unbounded weights back before the columns change.
  for (std::size_t k = 0; k < m_rows.size(); ++k) W.row(m_rows[k]) = m_unbounded.row(static_cast<Index>(k));
  field.apply(m_E, columns, W);
  bound(field, W);
}

Weights FieldSampler::evaluate(const CoordinateField& field) {
  Weights W(m_E.rows(), field.controls());
  field.apply(m_E, {}, W);
  bound(field, W);
  return W;
}

}  // namespace kc::app
