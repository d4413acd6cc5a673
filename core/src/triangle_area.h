#pragma once
// Private to kc::core: the signed area of a mesh triangle.

#include <array>

#include "kc/core/types.h"

namespace kc::detail {

/// Twice the signed area of triangle t (vertex rows of P): > 0 when counter-clockwise in the
/// plane's y-up orientation.
inline double signedArea2(const Points& P, const std::array<int, 3>& t) {
  const double ax = P(t[1], 0) - P(t[0], 0), ay = P(t[1], 1) - P(t[0], 1);
  const double bx = P(t[2], 0) - P(t[0], 0), by = P(t[2], 1) - P(t[0], 1);
  return ax * by - ay * bx;
}

}  // namespace kc::detail
