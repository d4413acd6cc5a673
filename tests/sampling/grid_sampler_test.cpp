// Grid sampler: regions, kinds, edge spacing and input checks.
#include <gtest/gtest.h>

#include <stdexcept>

#include "kc/sampling/grid_sampler.h"
#include "kc/sampling/sampler.h"
#include "test_shapes.h"

namespace kc::sampling {
namespace {

SamplingOptions gridOptions(double h) {
  SamplingOptions o;
  o.spacing = h;
  o.width = 400;
  o.height = 300;
  o.kind = SamplerKind::Grid;
  return o;
}

TEST(GridSampler, ControlsFirstThenEdgesThenFree) {
  const Cage cage = test::starCage();
  SamplingReport report;
  const SampleSet S = sample(cage, gridOptions(8.0), &report);
  const Index m = cage.size();
  ASSERT_NO_THROW(S.validate(m));
  for (Index i = 0; i < m; ++i) {
    EXPECT_EQ(S.kind[static_cast<std::size_t>(i)], SampleKind::Control);
    EXPECT_EQ(S.X.row(i), cage.C.row(i));
  }
  Index i = m;
  while (i < S.size() && S.kind[static_cast<std::size_t>(i)] == SampleKind::Edge) ++i;
  EXPECT_EQ(i - m, report.edge);
  for (; i < S.size(); ++i) {
    const SampleKind k = S.kind[static_cast<std::size_t>(i)];
    EXPECT_TRUE(k == SampleKind::Interior || k == SampleKind::Exterior) << "sample " << i;
    EXPECT_EQ(S.edge(i, 0), -1);
  }
  EXPECT_EQ(report.controls, m);
  EXPECT_EQ(report.controls + report.edge + report.interior + report.exterior, S.size());
  EXPECT_GT(report.interior, 100);
  EXPECT_GT(report.exterior, 100);
}

TEST(GridSampler, RegionsMatchInsideTestAndKeepAwayFromCage) {
  for (const Cage& cage : {test::convexCage(), test::starCage(), test::uCage(20.0)}) {
    const double h = 8.0;
    const SampleSet S = sample(cage, gridOptions(h));
    for (Index i = cage.size(); i < S.size(); ++i) {
      const Vec2 x = S.X.row(i);
      const SampleKind k = S.kind[static_cast<std::size_t>(i)];
      if (k == SampleKind::Edge) {
        EXPECT_LT(distanceToCage(cage, x), 1e-9);
        continue;
      }
      EXPECT_EQ(k == SampleKind::Interior, insideCage(cage, x)) << "sample " << i;
      EXPECT_GE(distanceToCage(cage, x), 0.5 * h - 1e-9);
    }
  }
}

TEST(GridSampler, CoversImageAndMargin) {
  const double h = 10.0;
  SamplingOptions o = gridOptions(h);
  const SampleSet S = sample(test::convexCage(), o);
  const Rect d = samplingDomain(o);
  EXPECT_DOUBLE_EQ(d.x0, -3 * h);
  EXPECT_DOUBLE_EQ(d.x1, 400 + 3 * h);
  for (Index i = 0; i < S.size(); ++i) EXPECT_TRUE(d.contains(S.X.row(i)));
  EXPECT_DOUBLE_EQ(S.X.col(0).minCoeff(), -30.0);
  EXPECT_DOUBLE_EQ(S.X.col(1).maxCoeff(), 330.0);
}

TEST(GridSampler, EdgeSamplesEvenlySpacedAtAboutH) {
  const Cage cage = test::starCage();
  const double h = 7.0;
  const SampleSet S = sample(cage, gridOptions(h));
  const auto edges = cageEdges(cage);
  for (const auto& [a, b] : edges) {
    const Vec2 A = cage.C.row(a), B = cage.C.row(b);
    std::vector<double> t{0.0, 1.0};
    for (Index i = 0; i < S.size(); ++i)
      if (S.kind[static_cast<std::size_t>(i)] == SampleKind::Edge && S.edge(i, 0) == a && S.edge(i, 1) == b)
        t.push_back((Vec2(S.X.row(i)) - A).dot(B - A) / (B - A).squaredNorm());
    std::sort(t.begin(), t.end());
    const double len = (B - A).norm();
    for (std::size_t k = 1; k < t.size(); ++k) {
      const double gap = (t[k] - t[k - 1]) * len;
      EXPECT_NEAR(gap, len / static_cast<double>(t.size() - 1), 1e-9);
      EXPECT_GT(gap, 0.66 * h);
      EXPECT_LT(gap, 1.5 * h);
    }
  }
}

TEST(GridSampler, RejectsBadSpacing) {
  const Cage cage = test::convexCage();
  for (double h : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity(), 500.0})
    EXPECT_THROW(sample(cage, gridOptions(h)), std::invalid_argument) << h;
}

/// The spacing the too-many-samples message names (throws a test failure when there is none).
double spacingNamedForTooManySamples() {
  try {
    sample(test::convexCage(), gridOptions(0.3));
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("400000"), std::string::npos) << msg;
    const std::size_t at = msg.find("at least");
    if (at == std::string::npos) throw std::runtime_error("no spacing named: " + msg);
    return std::stod(msg.substr(at + 9));
  }
  throw std::runtime_error("expected std::invalid_argument for spacing 0.3");
}

TEST(GridSampler, RejectsTooManySamplesNamingASpacingThatFits) {
  const double fits = spacingNamedForTooManySamples();
  EXPECT_GT(fits, 0.3);
  // Free samples dominate and scale as 1/h² (edge samples as 1/h): at 4× the named spacing the
  // count times 16 bounds the count at the named one (GridSamplerSlow samples it outright).
  const std::size_t coarse = std::size_t(sample(test::convexCage(), gridOptions(4.0 * fits)).size());
  EXPECT_LE(16 * coarse, std::size_t(kMaxSamples)) << "named spacing " << fits;
  EXPECT_GT(16 * coarse, std::size_t(kMaxSamples) / 2) << "named spacing " << fits << " is far coarser than needed";
}

TEST(GridSamplerSlow, TheSpacingNamedForTooManySamplesFits) {
  const double fits = spacingNamedForTooManySamples();
  EXPECT_NO_THROW(sample(test::convexCage(), gridOptions(fits))) << fits;
}

TEST(GridSampler, RejectsCageOutsideImage) {
  Cage cage = test::convexCage();
  cage.C.col(0).array() += 1000.0;
  EXPECT_THROW(sample(cage, gridOptions(8.0)), std::invalid_argument);
  SamplingOptions o = gridOptions(8.0);
  o.width = 0;
  EXPECT_THROW(sample(test::convexCage(), o), std::invalid_argument);
}

}  // namespace
}  // namespace kc::sampling
