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
  const Vec2 c1 = s->bound->cage.C.row(1).transpose();
  s->pointerInputs.push_back({PointerInput::Kind::Move, 0, s->view.toScreen(c1)});
  s->pointerInputs.push_back({PointerInput::Kind::Press, 0, s->view.toScreen(c1)});
  s->pointerInputs.push_back({PointerInput::Kind::Move, 0, s->view.toScreen(c1 + Vec2(-10, 5))});
  s->pointerInputs.push_back({PointerInput::Kind::Move, 0, s->view.toScreen(c1 + Vec2(-20, 30))});
  s->pointerInputs.push_back({PointerInput::Kind::Release, 0, s->view.toScreen(c1 + Vec2(-20, 30))});
  gui.frame(draw);
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(-20, 30), 1e-6)) << s->pose[1].translate.transpose();
  EXPECT_EQ(s->undo.undoCount(), 1u);
}

TEST(CanvasInput, HandlesCloserThanTheirSizeAreDrawnSmallerToStayApart) {
  // Screen points: a pair 8.8 px apart (two handles 5 px apart at 176% zoom), a pair 2 px apart,
  // and one alone.
  Points S(5, 2);
  S << 100, 100, 108.8, 100, 300, 300, 300, 302, 500, 100;
  const Eigen::VectorXd k = handleScales(S, 6.5);
  ASSERT_EQ(k.size(), 5);
  EXPECT_NEAR(k(0), 0.5 * 8.8 / 6.5, 1e-12);
  EXPECT_NEAR(k(1), k(0), 1e-12);
  EXPECT_LE(2.0 * 6.5 * k(0), 8.8 + 1e-9) << "the two handles' discs touch at most";
  EXPECT_EQ(k(2), kMinHandleScale);  // too close to keep apart: the smallest size, still visible
  EXPECT_EQ(k(3), kMinHandleScale);
  EXPECT_EQ(k(4), 1.0);
  EXPECT_EQ(handleScales(S.topRows(1), 6.5)(0), 1.0);
  // 13 px apart or more: full size.
  Points far(2, 2);
  far << 0, 0, 13, 0;
  EXPECT_EQ(handleScales(far, 6.5).minCoeff(), 1.0);
}

TEST(CanvasInput, TagsThatWouldCoverEachOtherAreMovedApart) {
  // Boxes 20×14 px: two at nearly the same place (two control points 3 px apart), a third that
  // would land on the second's new place, and one far away.
  Points at(4, 2), size(4, 2);
  at << 100, 100, 102, 103, 101, 118, 400, 100;
  size << 20, 14, 20, 14, 20, 14, 20, 14;
  const Points p = tagPlaces(at, size);
  ASSERT_EQ(p.rows(), 4);
  EXPECT_EQ(Vec2(p.row(0)), Vec2(100, 100));  // the first keeps its place
  EXPECT_EQ(Vec2(p.row(1)), Vec2(102, 116));  // just below the first
  EXPECT_EQ(Vec2(p.row(2)), Vec2(101, 132));  // below the second's new place
  EXPECT_EQ(Vec2(p.row(3)), Vec2(400, 100));  // clear: untouched
  for (Index i = 0; i < 4; ++i)
    for (Index j = 0; j < i; ++j) {
      const bool apart = p(i, 0) >= p(j, 0) + size(j, 0) || p(j, 0) >= p(i, 0) + size(i, 0) ||
                         p(i, 1) >= p(j, 1) + size(j, 1) || p(j, 1) >= p(i, 1) + size(i, 1);
      EXPECT_TRUE(apart) << i << " covers " << j;
    }
  EXPECT_EQ(tagPlaces(at.topRows(1), size.topRows(1)), at.topRows(1));
  // 20 tags at one place: each moves below the last, at most 8 times (then it may cover one).
  const Points pile = tagPlaces(Points::Constant(20, 2, 100.0), size.row(0).replicate(20, 1));
  for (Index i = 0; i <= 8; ++i) EXPECT_EQ(pile(i, 1), 100.0 + 16.0 * double(i)) << i;
  for (Index i = 9; i < 20; ++i) EXPECT_EQ(pile(i, 1), 100.0 + 16.0 * 8.0) << i;
}

}  // namespace
}  // namespace kc::ui
