#include "kc/app/field_sampler.h"

#include <stdexcept>

namespace kc::app {

FieldSampler::FieldSampler(const CoordinateField& field, const Points& P) {
  if (!field.ready()) throw std::invalid_argument("FieldSampler: the coordinate field is not computed");
  m_E = field.evaluationOperator(P);
}

void FieldSampler::updateColumns(const CoordinateField& field, std::span<const Index> columns, Weights& W) const {
  if (columns.empty()) return;
  field.apply(m_E, columns, W);
}

Weights FieldSampler::evaluate(const CoordinateField& field) const {
  Weights W(m_E.rows(), field.controls());
  field.apply(m_E, {}, W);
  return W;
}

}  // namespace kc::app
