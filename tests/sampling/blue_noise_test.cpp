// Blue-noise sampling by inverse mean shift: regions, kinds, quality bounds, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <random>
#include <string>

#include "kc/core/parallel.h"
#include "kc/sampling/blue_noise.h"
#include "kc/sampling/point_metrics.h"
#include "kc/sampling/sampler.h"
#include "test_shapes.h"

namespace kc::sampling {
namespace {

constexpr double kH = 8.0;

SamplingOptions blueOptions(double h = kH, std::uint64_t seed = 1) {
  SamplingOptions o;
  o.spacing = h;
  o.width = 400;
  o.height = 300;
  o.kind = SamplerKind::BlueNoise;
  o.seed = seed;
  return o;
}

struct Shape {
  const char* name;
  Cage cage;
};

std::vector<Shape> shapes(double h = kH) {
  return {{"convex", test::convexCage()}, {"star", test::starCage()}, {"u-gap-2h", test::uCage(2.0 * h)}};
}

/// Every shape sampled at spacing h: samples ordered controls | edges | frame | interior |
/// exterior, each in its region, free ones at least 0.3 h from the cage.
void expectKindsInOrderAndEverySampleInItsRegion(double h) {
  for (const Shape& shape : shapes(h)) {
    SCOPED_TRACE(shape.name);
    const Cage& cage = shape.cage;
    SamplingReport report;
    const SamplingOptions o = blueOptions(h);
    const SampleSet S = sample(cage, o, &report);
    const Index m = cage.size();
    ASSERT_NO_THROW(S.validate(m));
    const Rect domain = samplingDomain(o);
    // controls | edges | frame | interior | exterior
    const Index firstFrame = m + report.edge, firstFree = firstFrame + report.frame;
    const Index firstExterior = firstFree + report.interior - 0;
    EXPECT_EQ(report.controls, m);
    EXPECT_EQ(S.size(), m + report.edge + report.interior + report.exterior);
    EXPECT_TRUE(report.converged);
    for (Index i = 0; i < S.size(); ++i) {
      const Vec2 x = S.X.row(i);
      const SampleKind k = S.kind[static_cast<std::size_t>(i)];
      EXPECT_TRUE(domain.contains(x)) << i;
      if (i < m) {
        EXPECT_EQ(k, SampleKind::Control);
      } else if (i < firstFrame) {
        ASSERT_EQ(k, SampleKind::Edge) << i;
        EXPECT_LT(distanceToCage(cage, x), 1e-9) << i;
      } else if (i < firstFree) {
        EXPECT_EQ(k, SampleKind::Exterior) << i;
        EXPECT_NEAR(domain.insideDistance(x), 0.0, 1e-9) << "frame point " << i << " on the domain boundary";
      } else {
        const bool interior = i < firstFree + report.interior;
        EXPECT_EQ(k, interior ? SampleKind::Interior : SampleKind::Exterior) << i;
        EXPECT_EQ(insideCage(cage, x), interior) << i;
        EXPECT_GE(distanceToCage(cage, x), 0.3 * h) << i;
      }
    }
    (void)firstExterior;
  }
}

TEST(BlueNoise, KindsInOrderAndEverySampleInItsRegion) { expectKindsInOrderAndEverySampleInItsRegion(1.5 * kH); }

TEST(BlueNoiseSlow, KindsInOrderAndEverySampleInItsRegionAtAFinerSpacing) {
  expectKindsInOrderAndEverySampleInItsRegion(kH);
}

/// Every shape sampled at spacing h: separation, fill distance and nearest-neighbour spread (in h).
void expectSeparationAndFillDistanceWithinBounds(double h) {
  for (const Shape& shape : shapes(h)) {
    SCOPED_TRACE(shape.name);
    SamplingReport report;
    const SamplingOptions o = blueOptions(h);
    const SampleSet S = sample(shape.cage, o, &report);
    const Index firstFree = S.size() - report.interior - (report.exterior - report.frame);
    const PointSetMetrics q = pointSetMetrics(S.X, h, samplingDomain(o), firstFree, h / 8.0);
    EXPECT_GE(q.separation, 0.6) << "free samples closer than 0.6 h to another sample";
    EXPECT_LE(q.fill, 0.9) << "largest empty circle";
    EXPECT_LT(q.nnCv, 0.1);
    EXPECT_NEAR(q.nnMean, 0.93, 0.07);
  }
}

TEST(BlueNoise, SeparationAndFillDistanceWithinBoundsOnSeveralShapes) { expectSeparationAndFillDistanceWithinBounds(1.5 * kH); }

TEST(BlueNoiseSlow, SeparationAndFillDistanceWithinBoundsAtAFinerSpacing) { expectSeparationAndFillDistanceWithinBounds(kH); }

TEST(BlueNoise, NarrowGapIsSampled) {
  const Cage cage = test::uCage(2.0 * kH);  // slot x ∈ [192, 208], y ∈ [60, 200]
  const SampleSet S = sample(cage, blueOptions());
  Index inSlot = 0;
  for (Index i = 0; i < S.size(); ++i)
    if (S.kind[static_cast<std::size_t>(i)] == SampleKind::Exterior && S.X(i, 0) > 192 && S.X(i, 0) < 208 && S.X(i, 1) > 70 &&
        S.X(i, 1) < 195)
      ++inSlot;
  EXPECT_GE(inSlot, 12) << "the 140-pixel slot should hold a column of exterior samples";
}

TEST(BlueNoise, FixedSamplesNeverMove) {
  const Cage cage = test::starCage();
  const SamplingOptions o = blueOptions();
  SamplingReport report;
  const SampleSet S = sample(cage, o, &report);
  const SampleSet B = boundarySamples(cage, kH);
  const Points F = dropNearCage(cage, framePoints(samplingDomain(o), kH), 0.5 * kH);
  ASSERT_EQ(report.frame, F.rows());
  EXPECT_EQ(S.X.topRows(B.size()), B.X);
  EXPECT_EQ(S.edge.topRows(B.size()), B.edge);
  EXPECT_EQ(S.X.middleRows(B.size(), F.rows()), F);
}

TEST(BlueNoiseSlow, SameSeedGivesIdenticalSamplesOnAnyThreadCount) {
  const Cage cage = test::starCage();
  SampleSet one, two, three;
  {
    ScopedThreadCount t(1);
    one = sample(cage, blueOptions(kH, 7));
  }
  {
    ScopedThreadCount t(2);
    two = sample(cage, blueOptions(kH, 7));
  }
  {
    ScopedThreadCount t(3);
    three = sample(cage, blueOptions(kH, 7));
  }
  ASSERT_EQ(one.size(), two.size());
  ASSERT_EQ(one.size(), three.size());
  EXPECT_TRUE(one.X == two.X) << "1 vs 2 threads";
  EXPECT_TRUE(one.X == three.X) << "1 vs 3 threads";
  EXPECT_EQ(one.kind, two.kind);
  const SampleSet other = sample(cage, blueOptions(kH, 8));
  EXPECT_FALSE(other.X.rows() == one.X.rows() && other.X == one.X) << "another seed gives another sampling";
}

TEST(BlueNoise, FreeCountFollowsRegionArea) {
  const Cage cage = test::convexCage();
  SamplingReport report;
  const SamplingOptions o = blueOptions();
  sample(cage, o, &report);
  const double area = std::abs(signedArea(cage.C));
  const double perCell = o.blueNoise.cellArea * kH * kH;
  // Interior: the area minus a band of about h/2 along the boundary, one sample per cell.
  const double perimeter = 2.0 * std::numbers::pi * 100.0;
  const double expected = (area - 0.5 * kH * perimeter) / perCell;
  EXPECT_NEAR(static_cast<double>(report.interior), expected, 0.1 * expected);
}

TEST(BlueNoiseSlow, RandomCagesMeetQualityBounds) {
  // A few random star-shaped polygons with 5-34 vertices, some with short edges and sharp spikes.
  int tried = 0;
  for (std::uint64_t t = 0; t < 12 && tried < 6; ++t) {
    std::mt19937_64 rng(t);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int m = 5 + static_cast<int>(rng() % 30);
    std::vector<Vec2> p;
    for (int i = 0; i < m; ++i) {
      const double a = 2.0 * std::numbers::pi * (i + 0.3 * u(rng)) / m, r = 30.0 + 110.0 * u(rng);
      p.emplace_back(200.0 + r * std::cos(a), 150.0 + 0.9 * r * std::sin(a));
    }
    const Cage cage = test::cageFrom(p);
    try {
      validateCage(cage);
    } catch (const std::invalid_argument&) {
      continue;
    }
    ++tried;
    SCOPED_TRACE("random cage " + std::to_string(t));
    SamplingReport r;
    const SamplingOptions o = blueOptions(kH, t);
    const SampleSet S = sample(cage, o, &r);
    EXPECT_TRUE(r.converged);
    const Index firstFree = S.size() - r.interior - (r.exterior - r.frame);
    for (Index i = firstFree; i < S.size(); ++i)
      EXPECT_EQ(insideCage(cage, S.X.row(i)), S.kind[static_cast<std::size_t>(i)] == SampleKind::Interior) << i;
    const PointSetMetrics q = pointSetMetrics(S.X, kH, samplingDomain(o), firstFree, kH / 8.0);
    EXPECT_GE(q.separation, 0.6);
    EXPECT_LE(q.fill, 0.9);
  }
  EXPECT_GE(tried, 4);
}

TEST(BlueNoise, OpenCageHasOnlyExteriorFreeSamplesThatDoNotCrossIt) {
  Cage stick;
  stick.C.resize(3, 2);
  stick.C << 100, 150, 200, 100, 300, 150;
  stick.closed = false;
  stick.edges = {{0, 1}, {1, 2}};
  SamplingReport r;
  const SampleSet S = sample(stick, blueOptions(), &r);
  ASSERT_NO_THROW(S.validate(3));
  EXPECT_EQ(r.interior, 0);
  EXPECT_GT(r.edge, 20);
  for (Index i = 3 + r.edge; i < S.size(); ++i) EXPECT_GE(distanceToCage(stick, S.X.row(i)), 0.3 * kH) << i;
}

TEST(BlueNoiseRectangle, ExactCountInsideWithBlueNoiseSpacing) {
  const Rect rect{-30, -30, 30, 30};
  InverseMeanShiftReport report;
  const Points X = blueNoiseRectangle(1024, rect, 3, {}, &report);
  ASSERT_EQ(X.rows(), 1024);
  for (Index i = 0; i < X.rows(); ++i) EXPECT_TRUE(rect.contains(X.row(i))) << i;
  EXPECT_TRUE(report.converged);
  const double h = std::sqrt(rect.area() / (1024 * kHexCellFactor));
  EXPECT_GE(minimumDistance(X) / h, 0.6);
  EXPECT_LE(fillDistance(X, Rect{-25, -25, 25, 25}, h / 8) / h, 0.9);
  EXPECT_TRUE(X == blueNoiseRectangle(1024, rect, 3)) << "deterministic in the seed";
  EXPECT_THROW(blueNoiseRectangle(0, rect, 1), std::invalid_argument);
}

}  // namespace
}  // namespace kc::sampling
