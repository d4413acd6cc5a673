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
  o.progress = [&](double f) {
    progress.push_back(f);
    return true;
  };
  SamplingReport r;
  const SampleSet S = sample(test::starCage(), o, &r);
  EXPECT_EQ(r.controls + r.edge + r.interior + r.exterior, S.size());
  EXPECT_GT(r.iterations, 10);
  EXPECT_TRUE(r.converged);
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), 1.0);
  for (std::size_t k = 1; k < progress.size(); ++k) EXPECT_GE(progress[k], progress[k - 1]);
}

TEST(Sampler, ProgressCallbackCancels) {
  // Returning false stops the relaxation with kc::Cancelled; a callback's own exception passes through.
  SamplingOptions o = options(SamplerKind::BlueNoise);
  int calls = 0;
  o.progress = [&](double) { return ++calls < 3; };
  EXPECT_THROW(sample(test::starCage(), o), kc::Cancelled);
  EXPECT_EQ(calls, 3);
  struct Stop {};
  o.progress = [](double f) -> bool {
    if (f > 0.0) throw Stop{};
    return true;
  };
  EXPECT_THROW(sample(test::starCage(), o), Stop);
}

/// A small square cage in a big picture: its band is much smaller than the frame.
Cage smallSquare() {
  Points C(4, 2);
  C << 300, 200, 400, 200, 400, 280, 300, 280;
  return Cage::polygon(C);
}

TEST(Sampler, ABandCoversTheCageBoxGrownByTheBandWithinTheFrame) {
  SamplingOptions o = options(SamplerKind::Grid);
  o.width = 800;
  o.height = 600;
  o.exterior = ExteriorExtent::Band;
  EXPECT_DOUBLE_EQ(resolvedBand(o), kExteriorBandSpacings * 8.0);
  const Rect r = sampledRegion(smallSquare(), o);
  EXPECT_DOUBLE_EQ(r.x0, 300 - resolvedBand(o));
  EXPECT_DOUBLE_EQ(r.y1, 280 + resolvedBand(o));
  o.band = 500.0;  // clipped to the frame (image plus its 24 px margin)
  const Rect clipped = sampledRegion(smallSquare(), o);
  EXPECT_DOUBLE_EQ(clipped.x0, -24.0);
  EXPECT_DOUBLE_EQ(clipped.y1, 624.0);
  o.exterior = ExteriorExtent::Frame;
  EXPECT_DOUBLE_EQ(sampledRegion(smallSquare(), o).x1, samplingDomain(o).x1);
}

TEST(Sampler, ABandStartsFromTheFramesSamples) {
  // Grid: the band's samples are exactly the frame's inside the band. Blue noise: the jittered
  // start inside the band is the frame's (the same cells and random stream), before relaxation.
  SamplingOptions o = options(SamplerKind::Grid);
  o.width = 800;
  o.height = 600;
  const SampleSet frame = sample(smallSquare(), o);
  o.exterior = ExteriorExtent::Band;
  const SampleSet band = sample(smallSquare(), o);
  const Rect r = sampledRegion(smallSquare(), o);
  Index inBand = 0;
  for (Index i = 0; i < frame.size(); ++i) inBand += r.contains(frame.X.row(i)) ? 1 : 0;
  ASSERT_EQ(band.size(), inBand);
  EXPECT_LT(band.size(), frame.size() / 4);
  for (Index i = 0, j = 0; i < frame.size(); ++i)
    if (r.contains(frame.X.row(i))) {
      EXPECT_EQ(frame.X.row(i), band.X.row(j)) << i;
      ++j;
    }

  const Rect frameRect = samplingDomain(o);
  Index interior = 0, interiorBand = 0;
  const Points all = jitteredStart(smallSquare(), frameRect, 8.0, 1.0, 7, interior);
  const Points part = jitteredStart(smallSquare(), r, 8.0, 1.0, 7, interiorBand, nullptr, &frameRect);
  Index kept = 0;
  for (Index i = 0; i < all.rows(); ++i) {
    const Vec2 p = all.row(i);
    if (r.insideDistance(p) < 4.0) continue;  // within h/2 of the band's side: dropped there
    bool found = false;
    for (Index j = 0; j < part.rows() && !found; ++j) found = part.row(j) == all.row(i);
    EXPECT_TRUE(found) << p.transpose();
    ++kept;
  }
  EXPECT_EQ(part.rows(), kept);
  EXPECT_EQ(interiorBand, interior);  // every start point inside the cage is in the band
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
