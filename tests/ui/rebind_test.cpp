// Binding again keeps the person's work: the pose carries over, paint strokes that cannot carry
// over are named in a question first, and the bind is one undo step (BindEdit) that brings the
// previous session, its weights and pose back bit for bit.
#include <gtest/gtest.h>

#include "kc/ui/frame.h"
#include "kc/ui/line_edits.h"
#include "kc/ui/rebind.h"
#include "kc/ui/rigidity_edits.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

PointerEvent at(const Vec2& p) {
  PointerEvent e;
  e.position = p;
  e.pickRadius = 6.0;
  return e;
}

/// Drags control `i` by `by` with the pose tool, then paints one stroke for it from a to b.
void poseAndPaint(AppState& s, Index i, const Vec2& by, const Vec2& a, const Vec2& b) {
  const Vec2 c = s.bound->cage.C.row(i).transpose();
  s.poseTool.press(s, at(c));
  s.poseTool.drag(s, at(c + by));
  s.poseTool.release(s, at(c + by));
  s.activeControl = i;
  s.brushTool.press(s, at(a));
  for (int k = 1; k <= 10; ++k) s.brushTool.drag(s, at(a + (b - a) * (k / 10.0)));
  s.brushTool.release(s, at(b));
  s.worker.waitFinished();
  pollWorker(s);
}

TEST(Rebind, AsksAboutStrokesKeepsThePoseAndIsOneUndoStep) {
  auto s = test::boundState(16.0);
  const Weights W0 = s->session->W;
  poseAndPaint(*s, 1, Vec2(-20, 15), Vec2(100, 60), Vec2(180, 90));
  ASSERT_EQ(s->undo.undoCount(), 2u);
  const auto painted = s->session;
  const Weights Wpainted = painted->W;
  ASSERT_FALSE(Wpainted == W0);
  const Pose pose = s->pose;
  EXPECT_EQ(strokesLostByRebind(*s), std::vector<std::string>{"paint w1"});

  // Bind asks first and changes nothing until answered.
  EXPECT_FALSE(requestBind(*s));
  ASSERT_TRUE(s->unsavedPrompt.has_value());
  EXPECT_EQ(s->unsavedPrompt->what, "Bind again");
  EXPECT_NE(s->unsavedPrompt->question.find("paint w1"), std::string::npos) << s->unsavedPrompt->question;
  EXPECT_EQ(s->session, painted);
  auto action = std::move(s->unsavedPrompt->run);
  s->unsavedPrompt.reset();
  action(*s);
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  ASSERT_NE(s->session, painted);
  const auto rebound = s->session;
  EXPECT_TRUE(s->session->W == W0) << "the new bind computes the weights anew (without the stroke)";
  ASSERT_EQ(s->pose.size(), pose.size());
  EXPECT_EQ(s->pose[1].translate, pose[1].translate) << "the pose is kept";
  ASSERT_EQ(s->undo.undoCount(), 3u) << "pose, stroke, bind";
  EXPECT_TRUE(std::holds_alternative<BindEdit>(s->undo.nextUndo()->edit));
  EXPECT_TRUE(strokesLostByRebind(*s).empty()) << "the stroke belongs to the previous bind now";

  // One undo: the previous session with the stroke, bit for bit, and the pose.
  ASSERT_TRUE(undo(*s));
  pollWorker(*s);
  EXPECT_EQ(s->session, painted);
  EXPECT_TRUE(s->session->W == Wpainted);
  EXPECT_EQ(s->pose[1].translate, pose[1].translate);
  EXPECT_TRUE(s->mesh.hasWeights());
  // The edits before the bind apply again: undo the stroke on the previous session.
  ASSERT_TRUE(undo(*s));
  pollWorker(*s);
  EXPECT_TRUE(s->session->W == W0);
  // And forward again to the new bind.
  ASSERT_TRUE(redo(*s));
  pollWorker(*s);
  ASSERT_TRUE(redo(*s));
  pollWorker(*s);
  EXPECT_EQ(s->session, rebound);
  EXPECT_EQ(s->pose[1].translate, pose[1].translate);
}

TEST(Rebind, WithoutStrokesBindsAtOnceAndKeepsThePose) {
  auto s = test::boundState(16.0);
  const auto before = s->session;
  Pose pose = s->pose;
  pose[2].translate = Vec2(7, -3);
  setPose(*s, pose);
  EXPECT_TRUE(requestBind(*s));
  pollWorker(*s);
  EXPECT_FALSE(s->unsavedPrompt.has_value());
  ASSERT_NE(s->session, before);
  EXPECT_EQ(s->pose[2].translate, Vec2(7, -3));
  EXPECT_EQ(s->undo.undoCount(), 1u);
  ASSERT_TRUE(undo(*s));
  EXPECT_EQ(s->session, before);
}

TEST(Rebind, TheUndoStackKeepsTheLastFourBinds) {
  auto s = test::boundState(20.0);
  for (int k = 0; k < 6; ++k) {
    ASSERT_TRUE(requestBind(*s));
    pollWorker(*s);
  }
  EXPECT_EQ(s->undo.undoCount(), 4u) << "each holds a whole session: the oldest went";
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(undo(*s));
  EXPECT_FALSE(s->undo.canUndo());
}

TEST(Rebind, ThePoseFollowsTheControlPointsThatStayed) {
  Points C(4, 2), D(5, 2);
  C << 0, 0, 10, 0, 10, 10, 0, 10;
  D << 0, 0, 5, 0, 10, 0, 10, 10, 0, 10;  // a point inserted on the first edge
  Pose pose = restPose(4);
  for (int i = 0; i < 4; ++i) pose[static_cast<std::size_t>(i)].translate = Vec2(i + 1, 0);
  const Pose carried = carriedPose(Cage::polygon(C), pose, Cage::polygon(D));
  ASSERT_EQ(carried.size(), 5u);
  EXPECT_EQ(carried[0].translate, Vec2(1, 0));
  EXPECT_EQ(carried[1].translate, Vec2::Zero()) << "a new point starts at rest";
  EXPECT_EQ(carried[2].translate, Vec2(2, 0));
  EXPECT_EQ(carried[4].translate, Vec2(4, 0));
  C(1, 0) = 12;  // a moved point, same count: handle by handle
  EXPECT_EQ(carriedPose(Cage::polygon(C), pose, Cage::polygon(D.topRows(4)))[1].translate, Vec2(2, 0));
}

/// Chooses LBC in the Bind panel and binds with it, as a person does after a KC bind.
template <class F>
void bindLbcInThePanel(test::HeadlessImGui& gui, AppState& s, F&& draw) {
  gui.frame(draw);
  gui.clickLabel(s, "LBC", draw);
  gui.frame(draw);
  gui.clickLabel(s, "Bind", draw);
  s.worker.waitFinished();
  pollWorker(s);
  ASSERT_TRUE(s.session);
  ASSERT_GT(s.bound->report.meshVertices(), 0) << (s.messages.empty() ? "" : s.messages.back().text);
}

TEST(Rebind, SwitchingToLbcKeepsTheKcBindOneClickAway) {
  test::HeadlessImGui gui;
  auto s = test::boundState(16.0);
  const auto kc = s->session;
  auto draw = [&] { drawFrame(*s); };
  ASSERT_NO_FATAL_FAILURE(bindLbcInThePanel(gui, *s, draw));
  // One click back to the KC bind (the Bind panel's "Previous bind"), one forward to LBC again.
  gui.frame(draw);
  gui.clickLabel(*s, "Previous bind", draw);
  EXPECT_EQ(s->session, kc);
  EXPECT_EQ(s->bindParams.backend, "kc") << "the Bind panel shows the bound session's backend";
  EXPECT_TRUE(s->bound->capabilities.painting);
  gui.frame(draw);
  gui.clickLabel(*s, "Next bind", draw);
  EXPECT_GT(s->bound->report.meshVertices(), 0);
  EXPECT_EQ(s->bindParams.backend, "lbc");
}

TEST(Rebind, AfterDraggingThePreviousBindIsStillOneClickAwayInThePresentPose) {
  // Compare KC and LBC on the same pose: bind LBC, drag a point, then Previous bind shows the KC
  // weights in that pose; Previous bind again (or Ctrl+Z) comes back to LBC in the same pose.
  test::HeadlessImGui gui;
  auto s = test::boundState(16.0);
  const auto kc = s->session;
  auto draw = [&] { drawFrame(*s); };
  ASSERT_NO_FATAL_FAILURE(bindLbcInThePanel(gui, *s, draw));
  const auto lbc = s->session;
  ASSERT_NE(lbc, kc);
  auto samePose = [](const Pose& x, const Pose& y) {
    if (x.size() != y.size()) return false;
    for (std::size_t k = 0; k < x.size(); ++k)
      if (x[k].translate != y[k].translate || x[k].rotate != y[k].rotate) return false;
    return true;
  };
  const Vec2 c = s->bound->cage.C.row(3).transpose();
  s->poseTool.press(*s, at(c));
  s->poseTool.drag(*s, at(c + Vec2(20, -10)));
  s->poseTool.release(*s, at(c + Vec2(20, -10)));
  const Pose dragged = s->pose;
  ASSERT_GT(dragged[3].translate.norm(), 10.0) << "the drag moved the point";
  ASSERT_NE(bindBehindPoses(s->undo), nullptr);
  gui.frame(draw);
  gui.clickLabel(*s, "Previous bind", draw);
  EXPECT_EQ(s->session, kc);
  EXPECT_EQ(s->bindParams.backend, "kc");
  EXPECT_TRUE(samePose(s->pose, dragged)) << "the KC weights in the pose the LBC bind had";
  // Back to LBC in that pose, by the same button; then by Ctrl+Z after a second drag and toggle.
  gui.frame(draw);
  gui.clickLabel(*s, "Previous bind", draw);
  EXPECT_EQ(s->session, lbc);
  EXPECT_TRUE(samePose(s->pose, dragged));
  const Vec2 moved = c + dragged[3].translate;
  s->poseTool.press(*s, at(moved));
  s->poseTool.drag(*s, at(moved + Vec2(0, 15)));
  s->poseTool.release(*s, at(moved + Vec2(0, 15)));
  const Pose again = s->pose;
  ASSERT_TRUE(showPreviousBind(*s));
  EXPECT_EQ(s->session, kc);
  EXPECT_TRUE(samePose(s->pose, again));
  undo(*s);
  EXPECT_EQ(s->session, lbc);
  EXPECT_TRUE(samePose(s->pose, again));
  // Undo runs back through every step to the KC bind the test started from, its pose at rest.
  while (s->undo.canUndo()) undo(*s);
  EXPECT_EQ(s->session, kc);
  EXPECT_TRUE(isRestPose(s->pose));
}

TEST(Rebind, SwitchingToLbcWithLinesAndRigidPaintAsksAndThePreviousBindKeepsThem) {
  // LBC keeps no lines straight and no parts rigid: Bind names them first, binds without them, and
  // the KC bind with them is one click back (found trying it: "Bind failed: ... (use --backend kc)",
  // then, for painted rigidity, "Cannot change the rigidity" after the LBC bind).
  test::HeadlessImGui gui;
  auto s = test::boundState(16.0);
  app::Structure lines;
  lines.lines.push_back({Vec2(60, 70), Vec2(190, 110), -1});
  ASSERT_TRUE(editLines(*s, lines, "line"));
  s->worker.waitFinished();
  pollWorker(*s);
  ASSERT_EQ(s->session->structure.lines.size(), 1u) << (s->messages.empty() ? "" : s->messages.back().text);
  std::vector<double> rho(static_cast<std::size_t>(s->session->samples.size()), 0.0);
  for (Index k = 0; k < s->session->samples.size(); ++k)
    if ((s->session->samples.X.row(k) - Vec2(180, 180).transpose()).norm() < 30.0) rho[static_cast<std::size_t>(k)] = 1.0;
  startRigidity(*s, rho, "rigid", true);  // a part painted rigid
  s->worker.waitFinished();
  pollWorker(*s);
  ASSERT_TRUE(anyRigid(boundRigidity(*s)));
  const auto kc = s->session;
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  gui.clickLabel(*s, "LBC", draw);
  EXPECT_TRUE(structureLeftOut(*s).find("LBC cannot keep lines and rigid regions") != std::string::npos) << structureLeftOut(*s);
  EXPECT_FALSE(requestBind(*s));
  ASSERT_TRUE(s->unsavedPrompt.has_value());
  EXPECT_NE(s->unsavedPrompt->question.find("binds without your lines"), std::string::npos) << s->unsavedPrompt->question;
  EXPECT_EQ(s->session, kc) << "nothing changes until the question is answered";
  auto action = std::move(s->unsavedPrompt->run);
  s->unsavedPrompt.reset();
  action(*s);
  s->worker.waitFinished();
  pollWorker(*s);
  ASSERT_NE(s->session, kc) << (s->messages.empty() ? "" : s->messages.back().text);
  EXPECT_GT(s->bound->report.meshVertices(), 0);
  EXPECT_TRUE(s->session->structure.lines.empty());
  for (const auto& m : s->messages) {  // nothing refused after the person said yes
    EXPECT_FALSE(m.error) << m.text;
    EXPECT_EQ(m.text.find("Cannot"), std::string::npos) << m.text;
  }
  gui.frame(draw);
  gui.clickLabel(*s, "Previous bind", draw);
  EXPECT_EQ(s->session, kc);
  EXPECT_EQ(s->lines.lines.size(), 1u) << "the lines come back with the KC bind";
  EXPECT_TRUE(anyRigid(boundRigidity(*s))) << "and the rigid part";
  // That KC bind sampled its one line uniformly; a line crossing it is still taken (graded rules).
  app::Structure crossing = s->lines;
  crossing.lines.push_back({Vec2(100, 40), Vec2(140, 150), -1});
  EXPECT_TRUE(editLines(*s, crossing, "line")) << (s->messages.empty() ? "" : s->messages.back().text);
  EXPECT_EQ(s->bindParams.backend, "kc");
}

TEST(Rebind, BeforeTheFirstBindLbcWithLinesIsRefusedAndTheLinesStay) {
  // Nothing would keep the lines: Bind says what to do instead of dropping them.
  auto s = test::unboundChecker(16.0);
  app::Structure lines;
  lines.lines.push_back({Vec2(60, 70), Vec2(190, 110), -1});
  ASSERT_TRUE(editLines(*s, lines, "line"));
  s->bindParams.backend = "lbc";
  EXPECT_FALSE(requestBind(*s));
  EXPECT_FALSE(s->bound);
  EXPECT_FALSE(s->unsavedPrompt.has_value());
  ASSERT_FALSE(s->messages.empty());
  EXPECT_TRUE(s->messages.back().error);
  EXPECT_EQ(s->messages.back().text, "LBC cannot keep lines: choose KC to bind with them; to bind LBC, delete them first (with KC chosen).");
  EXPECT_EQ(s->lines.lines.size(), 1u);
}

}  // namespace
}  // namespace kc::ui
