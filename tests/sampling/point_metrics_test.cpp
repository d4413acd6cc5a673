// Point-set metrics: separation, fill distance, nearest-neighbour statistics, radial spectrum.
#include <gtest/gtest.h>

#include "test_shapes.h"

#include <cmath>
#include <numbers>
#include <random>

#include "kc/sampling/blue_noise.h"
#include "kc/sampling/point_metrics.h"

namespace kc::sampling {
namespace {

using test::squareGrid;

TEST(PointMetrics, RegularGridHasKnownSeparationAndFill) {
  const double T = 2.0;
  const Points X = squareGrid(30, T);
  const Eigen::VectorXd nn = nearestNeighbourDistances(X);
  EXPECT_NEAR(nn.minCoeff(), T, 1e-12);
  EXPECT_NEAR(nn.maxCoeff(), T, 1e-12);
  EXPECT_NEAR(meanNearestNeighbourSpacing(X), T, 1e-12);
  const Rect inner{0, 0, 29 * T, 29 * T};
  // Largest empty circle of a square grid: half the cell diagonal, T/√2 (probe hits cell centres).
  EXPECT_NEAR(fillDistance(X, inner, T / 4), T / std::sqrt(2.0), 1e-12);
  const PointSetMetrics m = pointSetMetrics(X, T, inner, 0, T / 4);
  EXPECT_NEAR(m.separation, 1.0, 1e-12);
  EXPECT_NEAR(m.fill, 1.0 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(m.nnCv, 0.0, 1e-12);
}

TEST(PointMetrics, MinimumDistanceCountsOnlyPairsWithAMeasuredPoint) {
  Points X(4, 2);
  X << 0, 0, 0.1, 0, 5, 0, 7, 0;
  EXPECT_NEAR(minimumDistance(X), 0.1, 1e-12);
  EXPECT_NEAR(minimumDistance(X, 2), 2.0, 1e-12);
}

TEST(PointMetrics, SpectrumSeparatesGridWhiteAndBlueNoise) {
  const double T = 1.0;
  RadialSpectrumOptions o;
  o.omegaMax = 2.0 * 2.0 * std::numbers::pi / T;
  o.bins = 40;
  // Regular grid: nothing between the window's leakage and the first peak at 2π/T.
  const RadialSpectrum g = radialPowerSpectrum(squareGrid(40, T), o);
  for (Index b = 0; b < g.omega.size(); ++b)
    if (g.omega(b) > 1.0 && g.omega(b) < 0.9 * 2.0 * std::numbers::pi) {
      EXPECT_LT(g.power(b), 1e-3) << g.omega(b);
    }
  // Uniform random (white noise): power ≈ 1 at every frequency away from 0.
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 40.0);
  Points W(1600, 2);
  for (Index i = 0; i < W.rows(); ++i) W.row(i) << u(rng), u(rng);
  const RadialSpectrum w = radialPowerSpectrum(W, o);
  double mean = 0.0;
  int count = 0;
  for (Index b = 0; b < w.omega.size(); ++b)
    if (w.omega(b) > 2.0) mean += w.power(b), ++count;
  EXPECT_NEAR(mean / count, 1.0, 0.2);
  // Blue noise: a low-power gap below ~0.6 · 2π/h, power ≈ 1 far above.
  const Points B = blueNoiseRectangle(1600, Rect{0, 0, 40, 40}, 1);
  const RadialSpectrum bs = radialPowerSpectrum(B, o);
  const double h = std::sqrt(1600.0 / (1600 * kHexCellFactor));
  for (Index b = 0; b < bs.omega.size(); ++b)
    if (bs.omega(b) > 1.0 && bs.omega(b) < 0.5 * 2.0 * std::numbers::pi / h) {
      EXPECT_LT(bs.power(b), 0.05) << bs.omega(b);
    }
}

}  // namespace
}  // namespace kc::sampling
