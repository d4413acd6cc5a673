#pragma once
// Test support for the kernel and field tests: jittered grids, random points and random weights
// with fixed seeds, and the kernel of a spacing.

#include <numbers>
#include <ostream>
#include <random>

#include "kc/core/kernel/gaussian_kernel.h"
#include "kc/core/kernel/interpolator.h"
#include "kc/core/types.h"

namespace kc {
/// Test names and failure messages show the mode's name (gtest and ctest), not its bytes.
inline void PrintTo(InterpMode mode, std::ostream* os) { *os << (mode == InterpMode::Exact ? "exact" : "thesis"); }
}  // namespace kc

namespace kc::test {

/// n×n grid of spacing h with every point jittered by up to ±jitter·h (not a grid any more).
inline Points jitteredGrid(int n, double h, double jitter, unsigned seed, Vec2 origin = Vec2::Zero()) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter * h, jitter * h);
  Points X(n * n, 2);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) X.row(r * n + c) << origin.x() + c * h + u(rng), origin.y() + r * h + u(rng);
  return X;
}

/// count points uniform in [lo, hi]².
inline Points randomPointsIn(int count, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  Points P(count, 2);
  for (int i = 0; i < count; ++i) P.row(i) << u(rng), u(rng);
  return P;
}

/// rows×cols weights uniform in [0, 1].
inline Weights randomWeights(Index rows, Index cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Weights W(rows, cols);
  for (Index i = 0; i < W.size(); ++i) W.data()[i] = u(rng);
  return W;
}

/// The kernel at the automatic σ = 3h/π for samples of spacing h (thesis 3.28).
inline GaussianKernel kernelFor(double h) { return GaussianKernel::forSpacing(3.0 * h / std::numbers::pi, h); }

}  // namespace kc::test
