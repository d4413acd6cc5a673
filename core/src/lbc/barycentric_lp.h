#pragma once
// Private to core/lbc: the inner LP of the LBC duality-gap certificate,
//   min q·w  over w ∈ ℝ^m, w ≥ 0, Σ_j w_j = 1, Σ_j w_j c_j = x,
// (x inside the convex hull of the controls c_j), by the simplex method on its three equality
// constraints: a basis is a triangle of controls containing x.

#include <array>
#include <vector>

#include "kc/core/types.h"

namespace kc::detail {

class BarycentricLp {
 public:
  /// C: m×2 control positions (m ≥ 3, not all collinear).
  explicit BarycentricLp(const Points& C);

  /// A lower bound on the minimum above, equal to it (to round-off) when the simplex finishes
  /// within its pivot cap. For the multipliers λ ∈ ℝ³ of the last basis,
  ///   q·w = λ·(x, 1) + Σ_j w_j r_j ≥ λ·(x, 1) + min(0, min_j r_j),  r_j = q_j − λ·(c_j, 1),
  /// for every feasible w (Σ w = 1, w ≥ 0), so the value is a lower bound whatever the pivots
  /// did. basis: a starting triangle (e.g. the previous point's; basis[0] < 0 = none), replaced
  /// by the last basis. q: m values.
  double lowerBound(const Vec2& x, const double* q, std::array<int, 3>& basis) const;

 private:
  Points m_C;
  std::vector<std::array<int, 3>> m_fan;  // a fan triangulation of the controls' convex hull
};

}  // namespace kc::detail
