// The automatic spacing of a bind (issue 11): 6 px while the sample estimate fits the budget,
// larger on big pictures so the estimate stays at the budget instead of growing with pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "kc/app/file_io.h"
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

/// A rectangle over the middle of a w×h picture with a slot `gap` px wide cut in from its bottom.
Cage slotCage(int w, int h, double gap) {
  const double x0 = 0.25 * w, x1 = 0.75 * w, y0 = 0.3 * h, y1 = 0.7 * h, xm = 0.5 * w;
  Points C(8, 2);
  C << x0, y0, x1, y0, x1, y1, xm + gap / 2, y1, xm + gap / 2, y0 + 0.1 * h, xm - gap / 2, y0 + 0.1 * h, xm - gap / 2, y1, x0, y1;
  return Cage::polygon(C);
}

TEST(AutoSpacing, NarrowPlacesKeepTwoSamplesAcross) {
  // At 12 MP the budget alone would choose ~21 px; a 30 px slot asks for 15 px, which fits the limits.
  const BindParams p;
  const Cage wide = quarterCage(4384, 2736), slot = slotCage(4384, 2736, 30.0);
  const double hWide = automaticSpacing(wide, 4384, 2736, p), hSlot = automaticSpacing(slot, 4384, 2736, p);
  EXPECT_GT(hWide, 20.0);
  EXPECT_LE(hSlot, 15.0);
  EXPECT_GE(hSlot, 14.9);
  EXPECT_EQ(narrowFeatureWarning(slot, hSlot), "");
  EXPECT_NE(narrowFeatureWarning(slot, hWide), "");  // the budget's spacing would be too coarse there
}

TEST(AutoSpacing, WhenTheLimitsForbidItTheBindWarnsAndStillFits) {
  // A 12 px slot would need 6 px over 12 MP (above the sample limit): the spacing stops at the
  // smallest that fits the limits, and the warning names the slot's points and what resolves it.
  const BindParams p;
  const Cage slot = slotCage(4384, 2736, 12.0);
  BindParams q = p;
  q.spacing = automaticSpacing(slot, 4384, 2736, p);
  EXPECT_GT(q.spacing, 6.0);
  EXPECT_LT(q.spacing, 12.0);
  EXPECT_NO_THROW(checkBindCost(estimateBindCost(slot, 4384, 2736, q), q));
  const std::string warning = narrowFeatureWarning(slot, q.spacing);
  EXPECT_NE(warning.find("cage points 4 and 5"), std::string::npos) << warning;
  EXPECT_NE(warning.find("spacing 6 px or less"), std::string::npos) << warning;
}

TEST(AutoSpacing, TheBundledExamplesNeedNoWarning) {
  for (const char* name : {"checker", "star", "figure"}) {
    const Cage cage = loadCage(std::string(KC_SOURCE_DIR) + "/images/" + name + ".cage.json");
    EXPECT_EQ(narrowFeatureWarning(cage, BindParams{}.spacing), "") << name;
  }
}

}  // namespace
}  // namespace kc::app
