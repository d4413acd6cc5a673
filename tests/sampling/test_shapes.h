#pragma once
// Test cages shared by the sampling tests (image 400 × 300 pixels).

#include <cmath>
#include <numbers>
#include <vector>

#include "kc/core/cage.h"

namespace kc::test {

/// An n×n grid of spacing T starting at the origin.
inline Points squareGrid(int n, double T) {
  Points X(n * n, 2);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) X.row(i * n + j) << i * T, j * T;
  return X;
}

inline Cage cageFrom(const std::vector<Vec2>& pts) {
  Points C(static_cast<Index>(pts.size()), 2);
  for (std::size_t i = 0; i < pts.size(); ++i) C.row(static_cast<Index>(i)) = pts[i].transpose();
  return Cage::polygon(C);
}

/// Convex hexagon.
inline Cage convexCage() {
  std::vector<Vec2> p;
  for (int i = 0; i < 6; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 6.0;
    p.emplace_back(200.0 + 110.0 * std::cos(a), 150.0 + 95.0 * std::sin(a));
  }
  return cageFrom(p);
}

/// Five-pointed star, ten control points (thesis 6.2.1).
inline Cage starCage() {
  std::vector<Vec2> p;
  for (int i = 0; i < 10; ++i) {
    const double a = -std::numbers::pi / 2.0 + std::numbers::pi * i / 5.0;
    const double r = (i % 2 == 0) ? 125.0 : 52.0;
    p.emplace_back(200.0 + r * std::cos(a), 155.0 + r * std::sin(a));
  }
  return cageFrom(p);
}

/// U shape whose slot (exterior) is `gap` pixels wide.
inline Cage uCage(double gap) {
  const double c = 200.0, g = 0.5 * gap;
  return cageFrom({{80, 60}, {c - g, 60}, {c - g, 200}, {c + g, 200}, {c + g, 60}, {320, 60}, {320, 250}, {80, 250}});
}

}  // namespace kc::test
