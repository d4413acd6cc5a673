#pragma once
/// A coordinate field evaluated at a fixed set of points (e.g. warp-mesh vertices), backend-neutral:
/// the evaluation operator E(P) is cached, so after an edit that changed a few controls' columns
/// only those columns are re-evaluated (one sparse row product per point and column).

#include <memory>
#include <span>
#include <vector>

#include "kc/core/field/field.h"

namespace kc::app {

class FieldSampler {
 public:
  FieldSampler() = default;
  /// Caches E(P) (#P×nodes, sparse) of `field` for the rows of P. The field must be ready().
  FieldSampler(const CoordinateField& field, const Points& P);

  Index size() const { return m_E.rows(); }
  /// w(P) = E(P)·Coef of `field` (the field the sampler was built for, possibly updated since),
  /// then the field's lobe bound (CoordinateField::lobeBound): #P×m, what field.weightsAt(P) gives.
  Weights evaluate(const CoordinateField& field);
  /// Recomputes only `columns` of W (#P×m: this sampler's last evaluate() or updateColumns()
  /// result, not changed since) from the field's current coefficients; with a lobe bound, the rows
  /// it changed are projected again from their unbounded weights, which the sampler keeps.
  void updateColumns(const CoordinateField& field, std::span<const Index> columns, Weights& W);

 private:
  void bound(const CoordinateField& field, Weights& W);

  SparseRowMatrix m_E;  // #P×nodes
  Points m_P;
  std::vector<Index> m_rows;  // the rows the lobe bound changed (increasing) …
  RowMatrix m_unbounded;      // … and their unbounded weights
  std::shared_ptr<const LobeBound> m_boundsOf;  // the bound (kept alive: compared by address) whose ℓ at the points …
  std::vector<double> m_bounds;                 // … this is
};

}  // namespace kc::app
