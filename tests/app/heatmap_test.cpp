#include "kc/app/heatmap.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace kc::app {
namespace {

/// Linear weights over [0, w−1]: w0 = 1 − x/(w−1), w1 = x/(w−1), w2 = 0.
WeightFunction rampWeights(int w) {
  return [w](const Points& P) {
    Weights W = Weights::Zero(P.rows(), 3);
    for (Index p = 0; p < P.rows(); ++p) {
      W(p, 1) = P(p, 0) / (w - 1);
      W(p, 0) = 1 - W(p, 1);
    }
    return W;
  };
}

Cage triangleCage() {
  Points C(3, 2);
  C << 5, 5, 90, 10, 40, 70;
  return Cage::polygon(C);
}

TEST(Heatmap, ColourMapEnds) {
  EXPECT_EQ(heatColor(0.0), (Rgba{68, 1, 84, 255}));
  EXPECT_EQ(heatColor(1.0), (Rgba{253, 231, 37, 255}));
  EXPECT_EQ(heatColor(-3.0), heatColor(0.0));
  EXPECT_EQ(heatColor(7.0), heatColor(1.0));
}

TEST(Heatmap, LinearScaleFollowsTheWeights) {
  HeatmapOptions opt;
  opt.drawCage = false;
  HeatmapReport rep;
  const Image img = weightHeatmap(rampWeights(101), triangleCage(), 101, 80, 1, opt, &rep);
  EXPECT_EQ(img.width, 101 + 100);  // colour bar on the right
  EXPECT_EQ(img.height, 80);
  EXPECT_NEAR(rep.minValue, 0.0, 1e-12);
  EXPECT_NEAR(rep.maxValue, 1.0, 1e-12);
  EXPECT_EQ(img.at(0, 40), heatColor(0.0));
  EXPECT_EQ(img.at(100, 40), heatColor(1.0));
  EXPECT_EQ(img.at(50, 40), heatColor(0.5));
  opt.colorBar = false;
  EXPECT_EQ(weightHeatmap(rampWeights(101), triangleCage(), 101, 80, 1, opt).width, 101);
}

TEST(Heatmap, LogScaleSpreadsDecades) {
  HeatmapOptions opt;
  opt.drawCage = false;
  opt.scale = HeatScale::Log;
  opt.logFloor = 1e-4;
  RowMatrix V(1, 3);
  V << 1e-4, 1e-2, 1.0;
  HeatmapReport rep;
  const Image img = colorizeField(V, opt, "w", &rep);
  EXPECT_EQ(img.at(0, 0), heatColor(0.0));
  EXPECT_EQ(img.at(1, 0), heatColor(0.5));
  EXPECT_EQ(img.at(2, 0), heatColor(1.0));
  EXPECT_DOUBLE_EQ(rep.lowEnd, 1e-4);
}

TEST(Heatmap, CageIsDrawnAndBadControlRejected) {
  HeatmapOptions opt;
  const Image with = weightHeatmap(rampWeights(101), triangleCage(), 101, 80, 0, opt);
  opt.drawCage = false;
  const Image without = weightHeatmap(rampWeights(101), triangleCage(), 101, 80, 0, opt);
  EXPECT_NE(with.at(47, 7).r, without.at(47, 7).r);  // on the first edge
  EXPECT_THROW(weightHeatmap(rampWeights(101), triangleCage(), 101, 80, 3, opt), std::invalid_argument);
  EXPECT_THROW(weightHeatmap(rampWeights(101), triangleCage(), 0, 80, 0, opt), std::invalid_argument);
}

TEST(Heatmap, OverlaysDrawCagesAndSamples) {
  Image img(100, 80, Rgba{0, 0, 0, 255});
  const Cage cage = triangleCage();
  drawCage(img, cage, Rgba{255, 255, 255, 255});
  EXPECT_GT(img.at(5, 5).r, 100);  // control point dot
  Points P = cage.C;
  P.col(1).array() += 5;
  OverlayStyle style;
  drawDeformedCage(img, cage, P, style);
  EXPECT_EQ(img.at(90, 15).r, style.deformedCage.r);
  SampleSet s;
  s.X.resize(2, 2);
  s.X << 60, 60, 20, 60;
  s.kind = {SampleKind::Interior, SampleKind::Exterior};
  drawSamples(img, s);
  EXPECT_EQ(img.at(60, 60), sampleColor(SampleKind::Interior));
  EXPECT_EQ(img.at(20, 60), sampleColor(SampleKind::Exterior));
  EXPECT_THROW(drawDeformedCage(img, cage, Points(2, 2)), std::invalid_argument);
}

}  // namespace
}  // namespace kc::app
