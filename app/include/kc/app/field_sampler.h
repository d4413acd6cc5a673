#pragma once
/// The coordinate field sampled at a fixed set of points (e.g. warp-mesh vertices), with the kernel
/// rows k(p) cached: after an edit that changed a few controls' coefficients, only those columns
/// are re-evaluated (a sparse product per column instead of the kernel sums for every column).

#include <span>

#include "kc/app/session.h"
#include "kc/core/kernel/kernel_matrix.h"

namespace kc::app {

class FieldSampler {
 public:
  FieldSampler() = default;
  /// Caches k(p)ᵀ (#P×#S, sparse, thesis 3.32) for the rows of P. field.interpolator must be ok().
  FieldSampler(const CoordinateField& field, const Points& P);

  Index size() const { return m_P.rows(); }
  /// w(p) = k(p)ᵀU + [1 x y]B for every cached point: #P×m (6.3).
  Weights evaluate(const KernelCoefficients& coef) const;
  /// Recomputes only `columns` of W (#P×m) from coef.
  void updateColumns(const KernelCoefficients& coef, std::span<const Index> columns, Weights& W) const;

 private:
  SparseRowMatrix m_K;  // #P×#S
  Points m_P;
};

}  // namespace kc::app
