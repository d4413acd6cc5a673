#pragma once
/// Random points that are the same under every compiler. The arguments of one call are
/// unsequenced: Vec2(u(rng), u(rng)) draws y first under GCC and x first under Clang, so a test's
/// random problems differed between the Release build (GCC) and the sanitized one (Clang).
/// randomPoint draws y, then x: the problems the tests were first checked on (GCC's order).

#include "kc/core/types.h"

namespace kc::test {

/// (x, y) with y = dy(rng) drawn before x = dx(rng).
template <class DistX, class DistY, class Rng>
Vec2 randomPoint(DistX& dx, DistY& dy, Rng& rng) {
  const double y = dy(rng);
  const double x = dx(rng);
  return {x, y};
}

/// (x, y), both from d: y drawn first.
template <class Dist, class Rng>
Vec2 randomPoint(Dist& d, Rng& rng) {
  return randomPoint(d, d, rng);
}

}  // namespace kc::test
