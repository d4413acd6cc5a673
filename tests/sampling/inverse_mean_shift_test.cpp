// Inverse mean shift (thesis 6.4): the step, fixed samples, regions, stopping rule, periodic domain.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kc/core/parallel.h"
#include "kc/sampling/inverse_mean_shift.h"
#include "test_shapes.h"
#include "random_point.h"

namespace kc::sampling {
namespace {

TEST(InverseMeanShift, OneStepIsEquation64WithShiftedGaussian) {
  // One free sample between two fixed ones: x ← x + λ Σ (x − x_j)/s² (G_s − G_s(r)).
  Points X(3, 2);
  X << 0, 0, 10, 0, 4, 1;
  InverseMeanShiftOptions o;
  o.spacing = 8.0;
  o.maxIterations = 1;
  o.tolerance = 0.0;
  RelaxRegion region;
  region.domain = Rect{-100, -100, 100, 100};
  const Points before = X;
  relaxInverseMeanShift(X, 2, region, o);
  const double s = 0.6 * 8.0, lambda = 0.3 * s * s, r = 3.0 * s;
  auto g = [&](double d2) { return std::exp(-d2 / (2 * s * s)) - std::exp(-r * r / (2 * s * s)); };
  Vec2 expected = before.row(2);
  for (int j = 0; j < 2; ++j) {
    const Vec2 d = Vec2(before.row(2)) - Vec2(before.row(j));
    expected += lambda / (s * s) * d * g(d.squaredNorm());
  }
  EXPECT_NEAR(X(2, 0), expected.x(), 1e-5);  // the Gaussian is tabulated (relative error ~1e-6)
  EXPECT_NEAR(X(2, 1), expected.y(), 1e-5);
  EXPECT_EQ(X.topRows(2), before.topRows(2)) << "fixed rows never move";
}

TEST(InverseMeanShift, CrowdedSamplesNeverLeaveTheCage) {
  // 60 samples squeezed into a small square push hard against its edges.
  const Cage cage = test::cageFrom({{0, 0}, {40, 0}, {40, 40}, {0, 40}});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(4.0, 36.0);
  Points X(4 + 60, 2);
  X.topRows(4) = cage.C;
  for (Index i = 4; i < X.rows(); ++i) X.row(i) << u(rng), u(rng);
  const Points fixed = X.topRows(4);
  InverseMeanShiftOptions o;
  o.spacing = 8.0;
  o.maxIterations = 300;
  RelaxRegion region;
  region.cage = &cage;
  region.domain = Rect{-50, -50, 90, 90};
  const InverseMeanShiftReport report = relaxInverseMeanShift(X, 4, region, o);
  EXPECT_EQ(X.topRows(4), fixed);
  for (Index i = 4; i < X.rows(); ++i) {
    EXPECT_TRUE(insideCage(cage, X.row(i))) << i;
    EXPECT_GE(distanceToCage(cage, X.row(i)), o.clearance * o.spacing - 1e-9) << i;
  }
  EXPECT_GT(report.rejectedMoves, 0) << "the test should actually push samples against the cage";
}

TEST(InverseMeanShift, StopsWhenLargestMoveFallsBelowTolerance) {
  const Cage cage = test::starCage();
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Points X(cage.size(), 2);
  X = cage.C;
  std::vector<Vec2> free;
  while (free.size() < 300) {
    const Vec2 p = Vec2(75, 30) + 250 * test::randomPoint(u, rng);
    if (insideCage(cage, p) && distanceToCage(cage, p) > 4.0) free.push_back(p);
  }
  X.conservativeResize(cage.size() + 300, 2);
  for (std::size_t k = 0; k < free.size(); ++k) X.row(cage.size() + static_cast<Index>(k)) = free[k].transpose();
  InverseMeanShiftOptions o;
  o.spacing = 8.0;
  RelaxRegion region;
  region.cage = &cage;
  region.domain = Rect{0, 0, 400, 300};
  const InverseMeanShiftReport report = relaxInverseMeanShift(X, cage.size(), region, o);
  EXPECT_TRUE(report.converged);
  EXPECT_LT(report.iterations, o.maxIterations);
  ASSERT_EQ(static_cast<int>(report.largestMoves.size()), report.iterations);
  EXPECT_LT(report.lastMove, o.tolerance);
  EXPECT_GT(report.largestMoves.front(), 10 * o.tolerance);
  for (Index i = cage.size(); i < X.rows(); ++i) EXPECT_TRUE(insideCage(cage, X.row(i)));
}

TEST(InverseMeanShift, IterationCapIsReported) {
  Points X(50, 2);
  std::mt19937_64 rng(1);
  for (Index i = 0; i < X.rows(); ++i) X.row(i) << static_cast<double>(rng() % 100), static_cast<double>(rng() % 100);
  InverseMeanShiftOptions o;
  o.spacing = 14.0;
  o.maxIterations = 3;
  RelaxRegion region;
  region.domain = Rect{0, 0, 100, 100};
  const InverseMeanShiftReport report = relaxInverseMeanShift(X, 0, region, o);
  EXPECT_EQ(report.iterations, 3);
  EXPECT_FALSE(report.converged);
}

TEST(InverseMeanShift, PeriodicDomainKeepsPointsInsideAndIsThreadCountIndependent) {
  const Rect rect{0, 0, 50, 30};
  Points start(40, 2);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (Index i = 0; i < start.rows(); ++i) start.row(i) << 50 * u(rng), 30 * u(rng);
  InverseMeanShiftOptions o;
  o.spacing = 6.0;
  RelaxRegion region;
  region.domain = rect;
  region.periodic = true;
  Points a = start, b = start;
  {
    ScopedThreadCount t(1);
    relaxInverseMeanShift(a, 0, region, o);
  }
  {
    ScopedThreadCount t(2);
    relaxInverseMeanShift(b, 0, region, o);
  }
  EXPECT_TRUE(a == b);
  for (Index i = 0; i < a.rows(); ++i) {
    EXPECT_GE(a(i, 0), 0.0);
    EXPECT_LT(a(i, 0), 50.0);
    EXPECT_GE(a(i, 1), 0.0);
    EXPECT_LT(a(i, 1), 30.0);
  }
}

TEST(InverseMeanShift, RejectsBadInput) {
  Points X = Points::Zero(3, 2);
  RelaxRegion region;
  region.domain = Rect{0, 0, 1, 1};
  InverseMeanShiftOptions o;
  EXPECT_THROW(relaxInverseMeanShift(X, 0, region, o), std::invalid_argument);  // spacing 0
  o.spacing = 1.0;
  EXPECT_THROW(relaxInverseMeanShift(X, 4, region, o), std::invalid_argument);
}

}  // namespace
}  // namespace kc::sampling
