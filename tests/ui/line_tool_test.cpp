// The line tool without a window (thesis 5.3): drawing a line re-binds with it and keeps the
// pose; invalid lines are refused with the reason; parallel groups, delete, undo/redo, cancel,
// sessions; the Lines panel's widgets say what they do.
#include <gtest/gtest.h>

#include <filesystem>
#include <span>

#include "cli_run.h"
#include "kc/app/line_metrics.h"
#include "kc/ui/frame.h"
#include "kc/ui/line_edits.h"
#include "stage_gate.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

PointerEvent at(const Vec2& p, MouseButton b = MouseButton::Left, bool shift = false) {
  PointerEvent e;
  e.position = p;
  e.button = b;
  e.shift = shift;
  e.pickRadius = 6.0;
  return e;
}

/// Press at a, drag and release at b with the line tool; then the window's next frames.
void drawLine(AppState& s, const Vec2& a, const Vec2& b) {
  s.lineTool.press(s, at(a));
  s.lineTool.drag(s, at(0.5 * (a + b)));
  s.lineTool.release(s, at(b));
  s.worker.waitFinished();
  pollWorker(s);
}

/// A click (press and release in place) with the line tool.
void click(AppState& s, const Vec2& p, bool shift = false) {
  s.lineTool.press(s, at(p, MouseButton::Left, shift));
  s.lineTool.release(s, at(p, MouseButton::Left, shift));
  s.worker.waitFinished();
  pollWorker(s);
}

void finish(AppState& s) {
  s.worker.waitFinished();
  pollWorker(s);
}

std::string lastMessage(const AppState& s) { return s.messages.empty() ? "" : s.messages.back().text; }

constexpr double kSpacing = 16.0;

/// The bound checker (256×256, cage = the image's border; h = 16 px, manual spacing) with the
/// line tool active.
std::unique_ptr<AppState> lineState() {
  auto s = test::boundState(kSpacing);
  s->autoSpacing = false;
  selectTool(*s, Tool::Lines);
  EXPECT_EQ(s->tool, Tool::Lines);
  return s;
}

TEST(LineTool, DrawingALineRebindsWithItAndKeepsThePose) {
  auto s = lineState();
  Pose pose = s->pose;
  pose[1].translate = Vec2(-20, 15);
  setPose(*s, pose);
  const app::Session* before = s->session.get();
  drawLine(*s, Vec2(60, 70), Vec2(190, 110));
  ASSERT_EQ(s->lines.lines.size(), 1u) << lastMessage(*s);
  ASSERT_TRUE(s->session);
  EXPECT_NE(s->session.get(), before) << "adding a line re-binds";
  ASSERT_EQ(s->session->structure.lines.size(), 1u);
  EXPECT_TRUE(s->session->samples.lines.empty()) << "exact lines are kept straight by the field, not by samples";
  EXPECT_TRUE(s->session->structure.lines[0].a.isApprox(Vec2(60, 70)));
  EXPECT_EQ(s->bound->lines.size(), 1u);
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(-20, 15))) << "the pose survives the re-bind";
  EXPECT_EQ(s->tool, Tool::Lines);
  EXPECT_EQ(s->lineSelection, std::vector<int>{0});
  EXPECT_TRUE(s->unsaved);
  // The bound line stays straight under random translations of the controls (to round-off).
  const app::LineFigures f = app::measureLines(*s->session, s->session->structure.lines, 20);
  EXPECT_LT(f.deviation, 1e-9);
  // The same line without the structure bends (the check above can fail).
  const app::LineFigures bare = app::measureLines(*test::boundState(kSpacing)->session, s->session->structure.lines, 20);
  EXPECT_GT(bare.deviation, 10.0 * std::max(f.deviation, 1e-3));
}

TEST(LineTool, ClickAtBothEndsDrawsALine) {
  auto s = lineState();
  click(*s, Vec2(60, 200));
  EXPECT_TRUE(s->lineTool.drawing());
  EXPECT_TRUE(s->lines.empty());
  click(*s, Vec2(200, 200));
  EXPECT_FALSE(s->lineTool.drawing());
  ASSERT_EQ(s->lines.lines.size(), 1u) << lastMessage(*s);
  EXPECT_EQ(s->session->structure.lines.size(), 1u);
}

/// Draws each case's line after line 0 and expects it refused with its reason: no new line, no
/// re-bind, no undo entry.
struct Refusal {
  Vec2 a, b;
  const char* reason;
};
void expectRefused(AppState& s, std::span<const Refusal> cases) {
  const app::Session* bound = s.session.get();
  const std::size_t undoCount = s.undo.undoCount();
  for (const Refusal& c : cases) {
    drawLine(s, c.a, c.b);
    EXPECT_EQ(s.lines.lines.size(), 1u);
    ASSERT_FALSE(s.messages.empty());
    EXPECT_TRUE(s.messages.back().error);
    EXPECT_NE(s.messages.back().text.find("Line refused: "), std::string::npos) << s.messages.back().text;
    EXPECT_NE(s.messages.back().text.find(c.reason), std::string::npos) << s.messages.back().text;
  }
  EXPECT_EQ(s.session.get(), bound) << "a refused line does not re-bind";
  EXPECT_EQ(s.undo.undoCount(), undoCount) << "nor is it recorded";
}

TEST(LineTool, InvalidLinesAreRefusedWithTheReason) {
  // A graded bind (the default) refuses only a line that leaves the cage or overlaps another.
  auto s = lineState();
  drawLine(*s, Vec2(60, 70), Vec2(190, 110));
  ASSERT_EQ(s->lines.lines.size(), 1u);
  const Refusal graded[] = {
      {Vec2(-30, 200), Vec2(120, 200), "cage"},         // outside the cage, crossing its edge
      {Vec2(255, 130), Vec2(125, 90), "overlaps line 0"},  // line 0 extended to the cage, over its second half
  };
  expectRefused(*s, graded);
  // A uniform one (--uniform-spacing) that makes lines linear through their samples (a session
  // written before the exact correction) keeps lines a spacing from the cage and from each other.
  // (A bound document with lines asks for graded, exact binds again, installSession: set it after line 0.)
  auto u = lineState();
  drawLine(*u, Vec2(60, 70), Vec2(190, 110));
  ASSERT_EQ(u->lines.lines.size(), 1u) << lastMessage(*u);
  u->bindParams.graded = false;
  u->bindParams.kc.exactLines = false;
  const Refusal uniform[] = {
      {Vec2(100, 40), Vec2(140, 150), "crosses line 0"},  // crossing the first line
      {Vec2(-30, 200), Vec2(120, 200), "cage"},           // outside the cage, crossing its edge
      {Vec2(60, 220), Vec2(100, 221), "shorter than"},    // too short (40 px < 3 spacings)
      {Vec2(60, 245), Vec2(200, 245), "cage edge"},       // closer than a spacing to the cage
  };
  expectRefused(*u, uniform);
  // The reason is the CLI's: the same structure through kcwarp-cli bind --structure names the same problem.
  EXPECT_EQ(linesProblem(*u, [&] {
              app::Structure st = u->lines;
              st.lines.push_back({Vec2(100, 40), Vec2(140, 150), -1});
              return st;
            }()),
            "line 1: the line crosses line 0");
}

TEST(LineTool, AGradedBindTakesCrossingLinesAndALineEndingAtTheCage) {
  // What a person draws (issue: structure on graded samplings): an X, and a line that runs up to
  // 1 px from the cage's edge. Both are bound as drawn and stay straight.
  auto s = lineState();
  drawLine(*s, Vec2(60, 70), Vec2(190, 110));
  drawLine(*s, Vec2(100, 40), Vec2(140, 150));  // crosses line 0
  drawLine(*s, Vec2(60, 200), Vec2(254, 200));  // ends 1 px from the cage's right edge (x = 255)
  ASSERT_EQ(s->lines.lines.size(), 3u) << lastMessage(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->session->structure.lines.size(), 3u);
  EXPECT_EQ(s->bound->lines.size(), 3u);
  const app::LineFigures f = app::measureLines(*s->session, s->session->structure.lines, 20);
  EXPECT_LT(f.deviation, 0.1);
}

TEST(LineTool, AnEndDrawnALittlePastTheOutlineEndsOnIt) {
  auto s = lineState();  // the cage is the picture's border, x = 255 on the right
  drawLine(*s, Vec2(60, 200), Vec2(259, 200));  // 4 px past it (the pick radius is 6)
  ASSERT_EQ(s->lines.lines.size(), 1u) << lastMessage(*s);
  EXPECT_NEAR(s->lines.lines[0].b.x(), 255.0, 1e-9);
  EXPECT_NEAR(s->lines.lines[0].b.y(), 200.0, 1e-9);
  EXPECT_TRUE(s->lines.lines[0].a.isApprox(Vec2(60, 200))) << "the end inside stays where it was drawn";
  ASSERT_TRUE(s->session);
  EXPECT_LT(app::measureLines(*s->session, s->session->structure.lines, 20).deviation, 0.1);
  // Further past the outline the line is refused as drawn.
  drawLine(*s, Vec2(60, 100), Vec2(275, 100));
  EXPECT_EQ(s->lines.lines.size(), 1u);
  EXPECT_NE(lastMessage(*s).find("not inside the cage"), std::string::npos) << lastMessage(*s);
}

TEST(LineTool, ADragThatStartsOnALineDrawsANewOneAndAClickOnItSelectsIt) {
  auto s = lineState();
  drawLine(*s, Vec2(50, 100), Vec2(200, 100));
  ASSERT_EQ(s->lines.lines.size(), 1u) << lastMessage(*s);
  // A second line 3 px below the first: its press lies within the first's pick radius (6 px).
  drawLine(*s, Vec2(50, 103), Vec2(200, 103));
  ASSERT_EQ(s->lines.lines.size(), 2u) << lastMessage(*s);
  EXPECT_TRUE(s->lines.lines[1].a.isApprox(Vec2(50, 103)));
  EXPECT_EQ(s->lineSelection, std::vector<int>{1}) << "the new line is selected";
  click(*s, Vec2(125, 99));  // on line 0 (also within line 1's radius; line 0 is nearer)
  EXPECT_EQ(s->lineSelection, std::vector<int>{0});
  EXPECT_FALSE(s->lineTool.drawing()) << "a click on a line starts no line";
  EXPECT_EQ(s->lines.lines.size(), 2u);
  click(*s, Vec2(125, 104), /*shift=*/true);  // adds line 1
  EXPECT_EQ(s->lineSelection, (std::vector<int>{0, 1}));
}

TEST(LineTool, ParallelGroupDeleteUndoRedo) {
  auto s = lineState();
  drawLine(*s, Vec2(50, 60), Vec2(200, 90));
  drawLine(*s, Vec2(50, 160), Vec2(200, 190));  // parallel to the first
  ASSERT_EQ(s->lines.lines.size(), 2u) << lastMessage(*s);
  std::vector<StructureLine> pair = s->session->structure.lines;  // the two lines, measured as a group
  pair[0].group = pair[1].group = 0;
  const double ungrouped = app::measureLines(*s->session, pair, 20).angle;
  click(*s, Vec2(125, 75));                     // selects line 0
  click(*s, Vec2(125, 175), /*shift=*/true);    // adds line 1
  ASSERT_EQ(s->lineSelection.size(), 2u);
  ASSERT_TRUE(groupSelectedLines(*s, "rails"));
  finish(*s);
  ASSERT_EQ(s->session->structure.groups, std::vector<std::string>{"rails"});
  EXPECT_EQ(s->session->structure.lines[0].group, 0);
  EXPECT_EQ(s->session->structure.lines[1].group, 0);
  const app::LineFigures f = app::measureLines(*s->session, s->session->structure.lines, 20);
  EXPECT_LT(f.angle, 0.05) << "issue 13: parallel lines stay parallel within 0.05 degrees";
  EXPECT_LT(f.deviation, 0.1);
  EXPECT_GT(ungrouped, 10.0 * std::max(f.angle, 1e-3)) << "straight but not grouped, they turn apart";

  // Deleting one line dissolves the group of two.
  s->lineSelection = {1};
  ASSERT_TRUE(deleteSelectedLines(*s));
  finish(*s);
  ASSERT_EQ(s->session->structure.lines.size(), 1u);
  EXPECT_EQ(s->session->structure.lines[0].group, -1);
  EXPECT_TRUE(s->session->structure.groups.empty());

  // Undo brings back the group, undo again the two ungrouped lines; redo goes forward again.
  ASSERT_TRUE(undo(*s));
  finish(*s);
  ASSERT_EQ(s->session->structure.lines.size(), 2u);
  EXPECT_EQ(s->session->structure.groups, std::vector<std::string>{"rails"});
  ASSERT_TRUE(undo(*s));
  finish(*s);
  EXPECT_TRUE(s->session->structure.groups.empty());
  EXPECT_EQ(s->session->structure.lines.size(), 2u);
  ASSERT_TRUE(redo(*s));
  finish(*s);
  EXPECT_EQ(s->session->structure.groups, std::vector<std::string>{"rails"});
  EXPECT_TRUE(sameLines(s->lines, s->session->structure));
}

TEST(LineTool, RightClickDeletesALine) {
  auto s = lineState();
  drawLine(*s, Vec2(60, 70), Vec2(190, 110));
  ASSERT_EQ(s->lines.lines.size(), 1u);
  s->lineTool.press(*s, at(Vec2(125, 90), MouseButton::Right));
  s->lineTool.release(*s, at(Vec2(125, 90), MouseButton::Right));
  finish(*s);
  EXPECT_TRUE(s->lines.empty());
  EXPECT_TRUE(s->session->structure.empty());
  EXPECT_TRUE(s->bound->lines.empty());
}

TEST(LineTool, PaintStrokesBeforeTheRebindLeaveTheHistory) {
  auto s = lineState();
  WeightEdit stroke;  // a recorded stroke whose rows belong to the old samples
  stroke.rows = {5};
  s->undo.push({"paint w0", stroke});
  drawLine(*s, Vec2(60, 70), Vec2(190, 110));
  ASSERT_EQ(s->lines.lines.size(), 1u);
  EXPECT_EQ(s->undo.undoCount(), 1u) << "only the line edit is left";
  bool told = false;
  for (const Message& m : s->messages) told = told || m.text.find("paint strokes") != std::string::npos;
  EXPECT_TRUE(told) << "the user is told why the history lost the strokes";
}

TEST(LineTool, ACancelledRebindKeepsTheBoundLinesAndTheEditBecomesRedoable) {
  test::StageGate gate("sampling");
  auto s = lineState();
  s->worker.setSynchronous(false);
  s->worker.setStageHook([&gate](const std::string& stage) { gate(stage); });
  const app::Session* bound = s->session.get();
  s->lineTool.press(*s, at(Vec2(60, 70)));
  s->lineTool.release(*s, at(Vec2(190, 110)));
  gate.waitInside();
  EXPECT_EQ(s->lines.lines.size(), 1u) << "the panel shows the new line while it binds";
  s->worker.cancel();
  pollWorker(*s);
  EXPECT_EQ(s->session.get(), bound);
  EXPECT_TRUE(s->lines.empty()) << "back to the bound session's lines";
  EXPECT_EQ(s->undo.undoCount(), 0u);
  EXPECT_EQ(s->undo.redoCount(), 1u);
  gate.release();
  s->worker.waitAbandoned();
  pollWorker(*s);
  EXPECT_EQ(s->session.get(), bound);
}

TEST(LineTool, LinesTravelWithTheSession) {
  auto s = lineState();
  drawLine(*s, Vec2(60, 70), Vec2(190, 110));
  drawLine(*s, Vec2(60, 170), Vec2(190, 210));
  s->lineSelection = {0, 1};
  ASSERT_TRUE(groupSelectedLines(*s, "pair"));
  finish(*s);
  const std::filesystem::path dir = test::scratchDir("line_tool_session");
  const std::string path = (dir / "lines.kcw.json").string();
  ASSERT_TRUE(startSaveSession(*s, path));
  finish(*s);
  auto t = test::boundState(kSpacing);
  ASSERT_TRUE(t->lines.empty());
  ASSERT_TRUE(startOpenSession(*t, path));
  finish(*t);
  EXPECT_TRUE(sameLines(t->lines, s->lines)) << lastMessage(*t);
  EXPECT_EQ(t->bound->lines.size(), 2u);
  EXPECT_EQ(t->lines.groups, std::vector<std::string>{"pair"});
  // Those lines are kept straight by the field (not sampled); the reopened document takes a line
  // crossing one of them.
  EXPECT_TRUE(t->session->params.kc.exactLines);
  selectTool(*t, Tool::Lines);
  drawLine(*t, Vec2(100, 40), Vec2(140, 150));
  EXPECT_EQ(t->lines.lines.size(), 3u) << lastMessage(*t);
}

TEST(LinesPanel, WidgetsSayWhatTheyDoAndMakeParallelGroups) {
  test::HeadlessImGui gui;
  auto s = lineState();
  drawLine(*s, Vec2(50, 60), Vec2(200, 90));
  drawLine(*s, Vec2(50, 160), Vec2(200, 191));
  s->lineSelection = {0, 1};
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  for (const char* label : {"Lines (L)", "line 0", "line 1", "Group name", "Make parallel", "Not parallel", "Delete line", "What holds? (hover)"})
    EXPECT_TRUE(s->widgets.count(label)) << label;
  std::erase_if(s->widgets, [](const auto& w) { return w.first.rfind("line ", 0) != 0 && w.first != "Lines (L)" &&
                                                      w.first != "Group name" && w.first != "Make parallel" &&
                                                      w.first != "Not parallel" && w.first != "Delete line" &&
                                                      w.first != "What holds? (hover)"; });
  EXPECT_EQ(gui.widgetsWithoutTooltip(*s, draw), "");
  gui.frame(draw);
  gui.clickLabel(*s, "Make parallel", draw);
  finish(*s);
  EXPECT_EQ(s->session->structure.groups, std::vector<std::string>{"parallel 1"});
}

TEST(LinesPanel, TheLineToolIsGreyedForLbc) {
  auto s = std::make_unique<AppState>();
  s->bindParams.backend = "lbc";
  selectTool(*s, Tool::Lines);
  EXPECT_NE(s->tool, Tool::Lines);
  EXPECT_NE(lastMessage(*s).find("KC"), std::string::npos);
}

}  // namespace
}  // namespace kc::ui

namespace kc::ui {
namespace {

TEST(LineTool, LinesDrawnBeforeTheBindAreBoundWithTheCage) {
  auto s = test::unboundChecker(kSpacing);
  ASSERT_TRUE(s->cageValid);
  selectTool(*s, Tool::Lines);
  ASSERT_EQ(s->tool, Tool::Lines);
  drawLine(*s, Vec2(60, 70), Vec2(190, 110));
  ASSERT_EQ(s->lines.lines.size(), 1u) << lastMessage(*s);
  EXPECT_FALSE(s->bound) << "no bind before the user asks for one";
  drawLine(*s, Vec2(-30, 200), Vec2(120, 200));  // leaves the cage: refused against the draft cage too
  EXPECT_EQ(s->lines.lines.size(), 1u);
  ASSERT_TRUE(startBind(*s));
  finish(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->session->structure.lines.size(), 1u);
  EXPECT_EQ(s->bound->lines.size(), 1u);
  EXPECT_LT(app::measureLines(*s->session, s->session->structure.lines, 20).deviation, 0.1);
}

}  // namespace
}  // namespace kc::ui
