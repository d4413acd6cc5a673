// The automatic spacing of a bind (issue 11): 6 px while the sample estimate fits the budget,
// larger on big pictures so the estimate stays at the budget instead of growing with pixels.
#include <gtest/gtest.h>

#include <cmath>

#include "kc/app/pipeline.h"

namespace kc::app {
namespace {

/// 34 points on r(θ) = 1 + 0.15 sin 3θ in a box of half the picture's width and height.
Cage quarterCage(int w, int h) {
  Points C(34, 2);
  for (int i = 0; i < 34; ++i) {
    const double t = 2 * M_PI * i / 34, r = 1 + 0.15 * std::sin(3 * t);
    C.row(i) << w / 2.0 + w / 4.0 / 1.15 * r * std::cos(t), h / 2.0 + h / 4.0 / 1.15 * r * std::sin(t);
  }
  return Cage::polygon(C);
}

TEST(AutoSpacing, SmallPicturesKeepTheDefault) {
  const BindParams p;
  EXPECT_EQ(automaticSpacing(quarterCage(320, 400), 320, 400, p), p.spacing);
  EXPECT_EQ(automaticSpacing(quarterCage(800, 600), 800, 600, p), p.spacing);
}

TEST(AutoSpacing, BigPicturesStayAtTheBudget) {
  const BindParams p;
  for (const auto& [w, h] : {std::pair{2309, 1732}, std::pair{4000, 3000}, std::pair{6000, 4000}}) {
    const Cage cage = quarterCage(w, h);
    ASSERT_GT(estimateBindCost(cage, w, h, p).samples, kAutoSpacingSamples) << w << "x" << h;  // 6 px would exceed it
    BindParams q = p;
    q.spacing = automaticSpacing(cage, w, h, p);
    EXPECT_GT(q.spacing, p.spacing) << w << "x" << h;
    const double samples = estimateBindCost(cage, w, h, q).samples;
    EXPECT_LE(samples, kAutoSpacingSamples * 1.02) << w << "x" << h;
    EXPECT_GE(samples, kAutoSpacingSamples * 0.9) << w << "x" << h;
    EXPECT_NO_THROW(checkBindCost(estimateBindCost(cage, w, h, q), q));
  }
}

TEST(AutoSpacing, OtherBackendsKeepTheirSpacing) {
  BindParams p;
  p.backend = "lbc";
  EXPECT_EQ(automaticSpacing(quarterCage(4000, 3000), 4000, 3000, p), p.spacing);
}

}  // namespace
}  // namespace kc::app
