#pragma once
/// A coordinate field evaluated at a fixed set of points (e.g. warp-mesh vertices), backend-neutral:
/// the evaluation operator E(P) is cached, so after an edit that changed a few controls' columns
/// only those columns are re-evaluated (one sparse row product per point and column).

#include <span>

#include "kc/core/field/field.h"

namespace kc::app {

class FieldSampler {
 public:
  FieldSampler() = default;
  /// Caches E(P) (#P×nodes, sparse) of `field` for the rows of P. The field must be ready().
  FieldSampler(const CoordinateField& field, const Points& P);

  Index size() const { return m_E.rows(); }
  /// w(P) = E(P)·Coef of `field` (the field the sampler was built for, possibly updated since): #P×m.
  Weights evaluate(const CoordinateField& field) const;
  /// Recomputes only `columns` of W (#P×m) from the field's current coefficients.
  void updateColumns(const CoordinateField& field, std::span<const Index> columns, Weights& W) const;

 private:
  SparseRowMatrix m_E;  // #P×nodes
};

}  // namespace kc::app
