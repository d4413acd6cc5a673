// Keyboard shortcuts (kc/ui/shortcuts.h) through Dear ImGui's null backend. ImGui samples key
// state once per frame, so the window also keeps every press its GLFW key callback sees
// (AppState::tappedKeys): a key that goes down and up between two frames — a quick tap while a big
// picture draws at a few frames per second — must still count, with the modifiers it was tapped with.
#include <gtest/gtest.h>

#include <GLFW/glfw3.h>

#include "kc/ui/edits.h"
#include "kc/ui/shortcuts.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

using test::HeadlessImGui;

TEST(Shortcuts, AKeyTappedBetweenTwoFramesCountsWithItsModifiers) {
  auto s = test::boundState();
  HeadlessImGui gui;
  const auto shortcuts = [&] { handleShortcuts(*s); };

  // C then P tapped: each frame sees no key down (ImGui's state has none), only the tap.
  s->tappedKeys = {{GLFW_KEY_C, 0}};
  gui.frame(shortcuts);
  EXPECT_EQ(s->tool, Tool::Cage);
  EXPECT_TRUE(s->tappedKeys.empty()) << "a frame consumes the taps";
  s->tappedKeys = {{GLFW_KEY_P, 0}};
  gui.frame(shortcuts);
  EXPECT_EQ(s->tool, Tool::Pose);

  // Ctrl+R tapped (ImGui's Ctrl is up by the frame): the pose is reset, the tool stays.
  Pose moved = s->pose;
  moved[0].translate = Vec2(7.0, -3.0);
  setPose(*s, moved);
  ASSERT_EQ(s->pose[0].translate, Vec2(7.0, -3.0));
  s->tappedKeys = {{GLFW_KEY_LEFT_CONTROL, GLFW_MOD_CONTROL}, {GLFW_KEY_R, GLFW_MOD_CONTROL}};
  gui.frame(shortcuts);
  EXPECT_EQ(s->pose[0].translate, Vec2(0.0, 0.0));
  EXPECT_EQ(s->tool, Tool::Pose);

  // No frame between: nothing happens until one runs; a frame with no tap changes nothing.
  setPose(*s, moved);
  gui.frame(shortcuts);
  EXPECT_EQ(s->pose[0].translate, Vec2(7.0, -3.0));
  EXPECT_EQ(s->tool, Tool::Pose);
}

TEST(Shortcuts, HoldingHHidesTheCageAndHoldingOShowsTheOriginal) {
  auto s = test::boundState();
  HeadlessImGui gui;
  const auto shortcuts = [&] { handleShortcuts(*s); };
  ImGuiIO& io = ImGui::GetIO();
  io.KeysDown[GLFW_KEY_H] = true;
  gui.frame(shortcuts);
  EXPECT_TRUE(s->hideCage);
  EXPECT_FALSE(s->showOriginal);
  gui.frame(shortcuts);
  EXPECT_TRUE(s->hideCage) << "while held";
  io.KeysDown[GLFW_KEY_O] = true;  // O wins: the original picture is drawn with its rest cage
  gui.frame(shortcuts);
  EXPECT_TRUE(s->showOriginal);
  EXPECT_FALSE(s->hideCage);
  io.KeysDown[GLFW_KEY_O] = io.KeysDown[GLFW_KEY_H] = false;
  gui.frame(shortcuts);
  EXPECT_FALSE(s->hideCage);
  EXPECT_FALSE(s->showOriginal);
  EXPECT_EQ(s->tool, Tool::Pose) << "H selects no tool";
  s->tool = Tool::Cage;  // the cage tool shows the picture and the cage being drawn, not the warp
  io.KeysDown[GLFW_KEY_H] = true;
  gui.frame(shortcuts);
  EXPECT_FALSE(s->hideCage);
  io.KeysDown[GLFW_KEY_H] = false;
}

}  // namespace
}  // namespace kc::ui
