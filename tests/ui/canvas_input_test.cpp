// The canvas replays the mouse events the window queued (AppState::pointerInputs) in order, with
// their positions: several clicks within one frame all reach the tool, and a press over a panel
// stays the panel's.
#include <gtest/gtest.h>

#include "kc/ui/canvas.h"
#include "kc/ui/frame.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

std::unique_ptr<AppState> pictureWithCageTool() {
  auto s = test::newPicture();
  s->pointerQueued = true;  // as the window does: the canvas reads the queue, not ImGui's mouse
  return s;
}

void clickQueued(AppState& s, const Vec2& screen) {
  s.pointerInputs.push_back({PointerInput::Kind::Move, 0, screen});
  s.pointerInputs.push_back({PointerInput::Kind::Press, 0, screen});
  s.pointerInputs.push_back({PointerInput::Kind::Release, 0, screen});
}

TEST(CanvasInput, ClicksQueuedWithinOneFrameAllReachTheTool) {
  test::HeadlessImGui gui;
  auto s = pictureWithCageTool();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);  // lays out the canvas and fits the picture
  const Vec2 points[] = {{100, 60}, {300, 60}, {320, 240}, {90, 240}};
  for (const Vec2& p : points) clickQueued(*s, s->view.toScreen(p));  // four clicks, one frame
  gui.frame(draw);
  ASSERT_EQ(s->cage.size(), 4) << "every click is a point";
  for (Index i = 0; i < 4; ++i) EXPECT_TRUE(s->cage.C.row(i).transpose().isApprox(points[i], 1e-6)) << i;
  EXPECT_TRUE(s->pointerInputs.empty()) << "a frame consumes the queue";
  EXPECT_LT(s->canvasDrag.button, 0) << "each press was released";
}

TEST(CanvasInput, APressOverThePanelIsNotTheCanvas) {
  test::HeadlessImGui gui;
  auto s = pictureWithCageTool();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  gui.frame(draw);
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  clickQueued(*s, Vec2(display.x - 100, display.y / 2));  // the side panel
  clickQueued(*s, s->view.toScreen(Vec2(200, 150)));
  gui.frame(draw);
  ASSERT_EQ(s->cage.size(), 1);
  EXPECT_TRUE(s->cage.C.row(0).transpose().isApprox(Vec2(200, 150), 1e-6));
}

TEST(CanvasInput, ADragInOneFrameMovesAndReleasesAtItsPositions) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  s->pointerQueued = true;
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  const Vec2 c1 = s->boundCage.C.row(1).transpose();
  s->pointerInputs.push_back({PointerInput::Kind::Move, 0, s->view.toScreen(c1)});
  s->pointerInputs.push_back({PointerInput::Kind::Press, 0, s->view.toScreen(c1)});
  s->pointerInputs.push_back({PointerInput::Kind::Move, 0, s->view.toScreen(c1 + Vec2(-10, 5))});
  s->pointerInputs.push_back({PointerInput::Kind::Move, 0, s->view.toScreen(c1 + Vec2(-20, 30))});
  s->pointerInputs.push_back({PointerInput::Kind::Release, 0, s->view.toScreen(c1 + Vec2(-20, 30))});
  gui.frame(draw);
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(-20, 30), 1e-6)) << s->pose[1].translate.transpose();
  EXPECT_EQ(s->undo.undoCount(), 1u);
}

}  // namespace
}  // namespace kc::ui
