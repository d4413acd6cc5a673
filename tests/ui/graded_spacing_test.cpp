// The Bind panel's spacing on a graded bind: the range it shows before the bind is the one the
// bind uses, and after the bind the session's (and its sigma range); the sample plot's spacings are
// the session's.
#include <gtest/gtest.h>

#include <cstdio>

#include "kc/app/pipeline.h"
#include "kc/ui/jobs.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

/// Two legs 3 px apart (the gap x ∈ [198.5, 201.5], y ∈ [120, 250]) on the 400×300 picture.
Cage legs() {
  Points C(8, 2);
  C << 100, 50, 300, 50, 300, 250, 201.5, 250, 201.5, 120, 198.5, 120, 198.5, 250, 100, 250;
  return Cage::polygon(C);
}

TEST(GradedSpacing, ThePanelShowsTheRangeTheBindUses) {
  auto s = test::newPicture();
  setDraftCage(*s, legs());
  ASSERT_TRUE(s->cageValid) << s->cageStatus;
  s->autoSpacing = true;
  const Document::ShownSpacing plan = spacingPlan(*s);
  EXPECT_LT(plan.minSpacing, 0.5 * plan.spacing) << "the 3 px gap is sampled finer than the rest";
  EXPECT_LE(plan.minSpacing, 3.0 / kFeatureSamples + 1e-9);
  EXPECT_GT(plan.points, 0.0);
  // The automatic sigma shown before the bind is a range too, in the plan's proportion.
  const auto [plannedMin, plannedMax] = plannedSigma(*s);
  EXPECT_DOUBLE_EQ(plannedMax, app::automaticSigma(plan.spacing));
  EXPECT_NEAR(plannedMin / plannedMax, plan.minSpacing / plan.spacing, 1e-12);
  ASSERT_TRUE(startBind(*s, true, false));
  s->worker.waitFinished();
  pollWorker(*s);
  ASSERT_TRUE(s->session) << "the bind did not finish: " << (s->messages.empty() ? "" : s->messages.back().text);
  const app::Session& session = *s->session;
  ASSERT_TRUE(session.sizing);
  EXPECT_DOUBLE_EQ(session.params.spacing, plan.spacing);
  EXPECT_DOUBLE_EQ(session.sizing->hMin(), plan.minSpacing);
  EXPECT_DOUBLE_EQ(s->bound->spacing, plan.spacing);
  EXPECT_DOUBLE_EQ(s->bound->minSpacing, plan.minSpacing);
  // The sigma shown after the bind is the session's, as a range: σ·h(x)/hMax at the smallest h.
  EXPECT_DOUBLE_EQ(s->bound->sigma, session.sigma);
  char sigma[64];
  std::snprintf(sigma, sizeof sigma, "%.2f-%.2f px", session.sigma * session.sizing->hMin() / session.params.spacing, session.sigma);
  EXPECT_EQ(boundSigmaText(*s), sigma);
  // Bind measures the spacing on the samples (3T/π): the range shown before it was about right.
  EXPECT_NEAR(plannedMax, session.sigma, 0.2 * session.sigma);
  EXPECT_NEAR(plannedMin, session.sigma * session.sizing->hMin() / session.params.spacing, 0.2 * plannedMin);
  // The count shown before the bind is the sampler's estimate: within a quarter of what it drew.
  const double drawn = double(s->bound->samples.size());
  EXPECT_NEAR(plan.points, drawn, 0.25 * drawn) << "estimated " << plan.points << ", sampled " << drawn;
  // The sample plot colours each sample by the session's h there.
  ASSERT_EQ(s->bound->sampleSpacing.size(), s->bound->samples.size());
  EXPECT_NEAR(s->bound->sampleSpacing.minCoeff(), plan.minSpacing, 0.5 * plan.minSpacing);
  EXPECT_DOUBLE_EQ(s->bound->sampleSpacing.maxCoeff(), plan.spacing);
}

TEST(GradedSpacing, AUniformBindShowsOneSpacing) {
  auto s = test::newPicture();
  setDraftCage(*s, legs());
  s->autoSpacing = true;
  s->bindParams.graded = false;
  const Document::ShownSpacing plan = spacingPlan(*s);
  EXPECT_EQ(plan.minSpacing, plan.spacing);
  // The plan follows the panel: grading on again changes it at once (no stale cache).
  s->bindParams.graded = true;
  EXPECT_LT(spacingPlan(*s).minSpacing, plan.spacing);
}

/// Binds the draft cage with `lines` at spacing 8 and checks that the plan shown before the bind is
/// what the bind used: the spacing, the smallest spacing of its sizing field and its grading.
/// Returns the plan.
Document::ShownSpacing expectPlanIsTheBinds(std::vector<StructureLine> lines, bool exactLines = false) {
  auto s = test::newPicture();
  Points C(4, 2);
  C << 100, 50, 300, 50, 300, 250, 100, 250;  // no narrow place
  setDraftCage(*s, Cage::polygon(C));
  EXPECT_TRUE(s->cageValid) << s->cageStatus;
  s->autoSpacing = false;
  s->bindParams.spacing = 8.0;
  s->bindParams.kc.exactLines = exactLines;
  s->lines.lines = std::move(lines);
  const Document::ShownSpacing plan = spacingPlan(*s);
  EXPECT_TRUE(startBind(*s, true, false));
  s->worker.waitFinished();
  pollWorker(*s);
  EXPECT_TRUE(s->session) << "the bind did not finish: " << (s->messages.empty() ? "" : s->messages.back().text);
  if (!s->session) return plan;
  const app::Session& session = *s->session;
  EXPECT_EQ(session.structure.lines.size(), s->lines.lines.size());
  EXPECT_DOUBLE_EQ(session.params.spacing, plan.spacing);
  EXPECT_DOUBLE_EQ(session.sizing ? session.sizing->hMin() : session.params.spacing, plan.minSpacing);
  EXPECT_EQ(session.params.graded && session.sizing, plan.minSpacing < plan.spacing);
  EXPECT_DOUBLE_EQ(s->bound->minSpacing, plan.minSpacing);
  const double drawn = double(s->bound->samples.size());
  EXPECT_NEAR(plan.points, drawn, 0.25 * drawn) << "estimated " << plan.points << ", sampled " << drawn;
  return plan;
}

TEST(GradedSpacing, LinesTheUniformRulesAcceptShowOneSpacing) {
  // A line 12 px (1.5 h) below the top edge: a graded sizing field would refine between them, but
  // the bind keeps the uniform sampling, and so does the plan.
  const Document::ShownSpacing plan = expectPlanIsTheBinds({{{150, 62}, {250, 62}}});
  EXPECT_EQ(plan.minSpacing, plan.spacing);
}

TEST(GradedSpacing, CrossingLinesShowTheGradedRange) {
  // The same line with two crossing lines: the bind samples graded, refined between line and edge.
  const Document::ShownSpacing plan =
      expectPlanIsTheBinds({{{150, 62}, {250, 62}}, {{150, 100}, {250, 200}}, {{150, 200}, {250, 100}}});
  EXPECT_LT(plan.minSpacing, plan.spacing);
}

TEST(GradedSpacing, ExactLinesKeepTheCagesSpacing) {
  // Lines kept straight by the field's correction (the default) are not sampled: the same crossing
  // lines leave the square's one spacing, and the plan says so.
  const Document::ShownSpacing plan =
      expectPlanIsTheBinds({{{150, 62}, {250, 62}}, {{150, 100}, {250, 200}}, {{150, 200}, {250, 100}}}, true);
  EXPECT_EQ(plan.minSpacing, plan.spacing);
}

TEST(GradedSpacing, ThePlanFollowsTheSliderWhenAutoSpacingIsOff) {
  auto s = test::newPicture();
  setDraftCage(*s, legs());
  s->autoSpacing = false;
  s->bindParams.spacing = 8.0;
  EXPECT_DOUBLE_EQ(spacingPlan(*s).spacing, 8.0);
  s->bindParams.spacing = 12.0;
  EXPECT_DOUBLE_EQ(spacingPlan(*s).spacing, 12.0);
}

}  // namespace
}  // namespace kc::ui
