#pragma once
// Cages for the LBC tests: a star polygon (like images/star) and an L-shaped polygon.

#include <cmath>
#include <numbers>

#include "kc/core/cage.h"

namespace kc::test {

/// A star with `tips` tips: 2·tips points alternating between radius R and r around (cx, cy).
inline Cage starCage(int tips = 5, double R = 140.0, double r = 60.0, double cx = 160.0, double cy = 160.0) {
  Points C(2 * tips, 2);
  for (int k = 0; k < 2 * tips; ++k) {
    const double a = -std::numbers::pi / 2 + k * std::numbers::pi / tips;
    const double rad = k % 2 == 0 ? R : r;
    C.row(k) << cx + rad * std::cos(a), cy + rad * std::sin(a);
  }
  return Cage::polygon(C);
}

/// An L: the square [0, 2s]² without its top-right quarter (6 points, one reflex corner at (s, s)).
inline Cage lCage(double s = 100.0) {
  Points C(6, 2);
  C << 0, 0, 2 * s, 0, 2 * s, s, s, s, s, 2 * s, 0, 2 * s;
  return Cage::polygon(C);
}

/// A square [50, 250]² with a slit 3 px wide cut in from below: x in [148.5, 151.5], y from 50 to
/// 200. Controls 1, 2 are the slit's left side, 3, 4 its right side.
inline Cage slitCage() {
  Points C(8, 2);
  C << 50, 50, 148.5, 50, 148.5, 200, 151.5, 200, 151.5, 50, 250, 50, 250, 250, 50, 250;
  return Cage::polygon(C);
}

}  // namespace kc::test
