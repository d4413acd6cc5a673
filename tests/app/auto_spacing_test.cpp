// The automatic spacing of a bind: 6 px while the sample estimate fits the budget,
// larger on big pictures so the estimate stays at the budget instead of growing with pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/core/lbc/cage_mesh.h"
#include "quarter_cage.h"
#include "kc/sampling/sampler.h"

namespace kc::app {
namespace {

using test::quarterCage;

TEST(AutoSpacing, SmallCagesKeepTheDefault) {
  BindParams p;
  p.exterior = sampling::ExteriorExtent::Band;
  EXPECT_EQ(automaticSpacing(quarterCage(320, 400), 320, 400, p), p.spacing);
  EXPECT_EQ(automaticSpacing(quarterCage(400, 300), 400, 300, p), p.spacing);
}

TEST(AutoSpacing, BigCagesStayAtTheBudget) {
  BindParams p;
  p.exterior = sampling::ExteriorExtent::Band;
  for (const auto& [w, h] : {std::pair{1155, 866}, std::pair{2309, 1732}, std::pair{4000, 3000}, std::pair{6000, 4000}}) {
    const Cage cage = quarterCage(w, h);
    ASSERT_GT(estimateBindCost(cage, w, h, p).samples, kAutoSpacingSamples) << w << "x" << h;  // 6 px would exceed it
    BindParams q = p;
    q.spacing = automaticSpacing(cage, w, h, p);
    EXPECT_GT(q.spacing, p.spacing) << w << "x" << h;
    const double samples = estimateBindCost(cage, w, h, q).samples;
    EXPECT_LE(samples, kAutoSpacingSamples * 1.05) << w << "x" << h;
    EXPECT_GE(samples, kAutoSpacingSamples * 0.9) << w << "x" << h;
    EXPECT_NO_THROW(checkBindCost(estimateBindCost(cage, w, h, q), q));
    // A whole-frame bind takes the same spacing (it follows the cage) while that fits the limits.
    BindParams frame = p;
    frame.exterior = sampling::ExteriorExtent::Frame;
    EXPECT_EQ(automaticSpacing(cage, w, h, frame), q.spacing) << w << "x" << h;
  }
}

TEST(AutoSpacing, ACageAndItsTenfoldCopyGetAboutTheSameSamples) {
  // A cage large enough to be over the budget at 6 px, and the same cage and picture 10× larger:
  // 10× the spacing, and the samples actually drawn (not only the estimate) within 5%.
  BindParams p;
  p.exterior = sampling::ExteriorExtent::Band;
  const Cage small = quarterCage(1200, 900), large = quarterCage(12000, 9000);
  BindParams a = p, b = p;
  a.spacing = automaticSpacing(small, 1200, 900, p);
  b.spacing = automaticSpacing(large, 12000, 9000, p);
  EXPECT_GT(a.spacing, p.spacing);
  EXPECT_NEAR(b.spacing / a.spacing, 10.0, 0.2);  // (the cage's m control samples do not scale)
  a.sampler = b.sampler = sampling::SamplerKind::Grid;  // the count without the relaxation's time
  const Index na = sampling::sample(small, samplingOptions(1200, 900, a)).size();
  const Index nb = sampling::sample(large, samplingOptions(12000, 9000, b)).size();
  EXPECT_NEAR(double(nb) / double(na), 1.0, 0.05) << na << " vs " << nb;
  EXPECT_NEAR(double(na), kAutoSpacingSamples, 0.15 * kAutoSpacingSamples);
}

TEST(AutoSpacing, TheLbcMeshFollowsItsVertexBudget) {
  // The LBC backend meshes the cage interior: about kAutoLbcVertices vertices at any scale (the
  // cage 10× larger, 10× the spacing), the 6 px floor for a small cage.
  BindParams p;
  p.backend = "lbc";
  const Cage small = quarterCage(1200, 900), large = quarterCage(12000, 9000);
  const double hSmall = automaticSpacing(small, 1200, 900, p), hLarge = automaticSpacing(large, 12000, 9000, p);
  EXPECT_GT(hSmall, p.spacing);
  EXPECT_NEAR(hLarge / hSmall, 10.0, 0.1);
  EXPECT_NEAR(estimateMeshVertices(small, hSmall), kAutoLbcVertices, 0.02 * kAutoLbcVertices);
  CageMeshOptions o;
  o.spacing = hSmall;
  EXPECT_NEAR(double(meshCageInterior(small, o).size()), kAutoLbcVertices, 0.15 * kAutoLbcVertices);
  EXPECT_EQ(automaticSpacing(quarterCage(320, 240), 320, 240, p), p.spacing);
}

/// A rectangle over the middle of a w×h picture with a slot `gap` px wide cut in from its bottom.
Cage slotCage(int w, int h, double gap) {
  const double x0 = 0.25 * w, x1 = 0.75 * w, y0 = 0.3 * h, y1 = 0.7 * h, xm = 0.5 * w;
  Points C(8, 2);
  C << x0, y0, x1, y0, x1, y1, xm + gap / 2, y1, xm + gap / 2, y0 + 0.1 * h, xm - gap / 2, y0 + 0.1 * h, xm - gap / 2, y1, x0, y1;
  return Cage::polygon(C);
}

TEST(AutoSpacing, NarrowPlacesKeepTwoSamplesAcross) {
  // A uniform bind (a graded one refines the slot instead): at 12 MP the budget alone would choose
  // ~40 px; a 30 px slot asks for 15 px, which fits the limits.
  BindParams p;
  p.graded = false;
  const Cage wide = quarterCage(4384, 2736), slot = slotCage(4384, 2736, 30.0);
  const double hWide = automaticSpacing(wide, 4384, 2736, p), hSlot = automaticSpacing(slot, 4384, 2736, p);
  EXPECT_GT(hWide, 20.0);
  EXPECT_LE(hSlot, 15.0);
  EXPECT_GE(hSlot, 14.9);
  EXPECT_EQ(narrowFeatureWarning(slot, hSlot), "");
  EXPECT_NE(narrowFeatureWarning(slot, 21.0), "");  // a coarser spacing would be too coarse there
}

TEST(AutoSpacing, WhenTheLimitsForbidItTheBindWarnsAndStillFits) {
  // A 12 px slot would need 6 px over 12 MP (above the sample limit): the spacing stops at the
  // smallest that fits the limits, and the warning names the slot's points and what resolves it
  // (a uniform bind of the whole frame; a graded one refines the slot).
  BindParams p = frameBindParams();
  p.graded = false;
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
