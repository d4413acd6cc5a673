#pragma once
// The big-picture benchmark's cage (bench/big_picture_bench.cpp), for tests of how costs follow
// the cage rather than the picture.

#include <cmath>

#include "kc/core/cage.h"

namespace kc::test {

/// 34 points on r(θ) = 1 + 0.15 sin 3θ in a box of half the picture's width and height, centred.
inline Cage quarterCage(int w, int h) {
  Points C(34, 2);
  for (int i = 0; i < 34; ++i) {
    const double t = 2 * M_PI * i / 34, r = 1 + 0.15 * std::sin(3 * t);
    C.row(i) << w / 2.0 + w / 4.0 / 1.15 * r * std::cos(t), h / 2.0 + h / 4.0 / 1.15 * r * std::sin(t);
  }
  return Cage::polygon(C);
}

}  // namespace kc::test
