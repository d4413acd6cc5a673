// The sampling entry point: options, validation, report, progress, plot data.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "kc/sampling/sample_plot.h"
#include "kc/sampling/sampler.h"
#include "test_shapes.h"

namespace kc::sampling {
namespace {

SamplingOptions options(SamplerKind kind, double h = 8.0) {
  SamplingOptions o;
  o.spacing = h;
  o.width = 400;
  o.height = 300;
  o.kind = kind;
  return o;
}

TEST(Sampler, BlueNoiseRejectsBadInputLikeGrid) {
  const Cage cage = test::starCage();
  for (double h : {0.0, -2.0, std::nan(""), 1000.0})
    EXPECT_THROW(sample(cage, options(SamplerKind::BlueNoise, h)), std::invalid_argument) << h;
  EXPECT_THROW(sample(cage, options(SamplerKind::BlueNoise, 0.5)), std::invalid_argument) << "too many samples";
  Cage far = cage;
  far.C.col(1).array() -= 400.0;
  EXPECT_THROW(sample(far, options(SamplerKind::BlueNoise)), std::invalid_argument);
  Cage broken = cage;
  broken.C.row(3) = broken.C.row(4);
  EXPECT_THROW(sample(broken, options(SamplerKind::BlueNoise)), std::invalid_argument);
  SamplingOptions o = options(SamplerKind::BlueNoise);
  o.blueNoise.cellArea = 0.0;
  EXPECT_THROW(sample(cage, o), std::invalid_argument);
}

TEST(Sampler, MarginDefaultsToThreeSpacingsAndCanBeSet) {
  SamplingOptions o = options(SamplerKind::BlueNoise);
  EXPECT_DOUBLE_EQ(resolvedMargin(o), 24.0);
  o.margin = 0.0;
  const Rect d = samplingDomain(o);
  EXPECT_EQ(d.x0, 0.0);
  EXPECT_EQ(d.y1, 300.0);
  SamplingReport r;
  const SampleSet S = sample(test::convexCage(), o, &r);
  for (Index i = 0; i < S.size(); ++i) EXPECT_TRUE(d.contains(S.X.row(i)));
  EXPECT_GT(r.frame, 0);
}

TEST(Sampler, ReportCountsAndProgress) {
  SamplingOptions o = options(SamplerKind::BlueNoise);
  std::vector<double> progress;
  o.progress = [&](double f) { progress.push_back(f); };
  SamplingReport r;
  const SampleSet S = sample(test::starCage(), o, &r);
  EXPECT_EQ(r.controls + r.edge + r.interior + r.exterior, S.size());
  EXPECT_GT(r.iterations, 10);
  EXPECT_TRUE(r.converged);
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), 1.0);
  for (std::size_t k = 1; k < progress.size(); ++k) EXPECT_GE(progress[k], progress[k - 1]);
}

TEST(Sampler, ProgressCallbackCanCancelByThrowing) {
  SamplingOptions o = options(SamplerKind::BlueNoise);
  struct Cancelled {};
  o.progress = [](double f) {
    if (f > 0.0) throw Cancelled{};
  };
  EXPECT_THROW(sample(test::starCage(), o), Cancelled);
}

TEST(SamplePlot, OneDotPerSampleControlsOnTop) {
  const SampleSet S = sample(test::starCage(), options(SamplerKind::Grid));
  const auto dots = samplePlot(S, 8.0);
  ASSERT_EQ(static_cast<Index>(dots.size()), S.size());
  const Rgb control = kindColor(SampleKind::Control);
  for (std::size_t k = dots.size() - 10; k < dots.size(); ++k) {
    EXPECT_EQ(dots[k].color.r, control.r);
    EXPECT_GT(dots[k].radius, dots.front().radius);
  }
  std::set<int> colours;
  for (SampleKind k : {SampleKind::Control, SampleKind::Edge, SampleKind::Line, SampleKind::Interior, SampleKind::Exterior}) {
    const Rgb c = kindColor(k);
    colours.insert(c.r << 16 | c.g << 8 | c.b);
  }
  EXPECT_EQ(colours.size(), 5u);
}

}  // namespace
}  // namespace kc::sampling
