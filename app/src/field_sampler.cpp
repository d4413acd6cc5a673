#include "kc/app/field_sampler.h"

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
  const LobeBound* b = field.lobeBound();
  if (!b) return;
  // Rows with a weight below −depth are the only ones the bound can change: keep their unbounded
  // weights, then project them.
  for (Index i = 0; i < W.rows(); ++i)
    if (W.row(i).minCoeff() < -b->depth()) m_rows.push_back(i);
  m_unbounded.resize(static_cast<Index>(m_rows.size()), W.cols());
  for (std::size_t k = 0; k < m_rows.size(); ++k) m_unbounded.row(static_cast<Index>(k)) = W.row(m_rows[k]);
  if (!m_rows.empty()) b->apply(m_P, W, m_rows);
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
