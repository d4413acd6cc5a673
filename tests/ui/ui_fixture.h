#pragma once
// Test support for kc::ui: an AppState with a small bound session (checker example, coarse
// spacing) and a headless Dear ImGui context (the null backend of example_null: no window).

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"
#include "kc/ui/app_state.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "scene_image.h"

namespace kc::test {

/// The checker example bound at `spacing`: the session the ctest fixture "ui_sessions" wrote
/// (tests/CMakeLists.txt, `kcwarp-cli bind --spacing`, once per run) when there is one, otherwise
/// bound here (a test executable run on its own).
inline std::shared_ptr<app::Session> boundChecker(const std::string& dir, int width, int height, double spacing) {
  if (const char* bound = std::getenv("KC_BOUND_EXAMPLES"); bound && spacing == std::floor(spacing)) {
    const std::string path = std::string(bound) + "/checker-" + std::to_string(static_cast<int>(spacing)) + ".kcw.json";
    if (std::filesystem::exists(path)) return std::make_shared<app::Session>(app::loadSession(path));
  }
  app::BindParams p;
  p.spacing = spacing;
  return std::make_shared<app::Session>(app::bind(app::loadCage(dir + "checker.cage.json"), width, height, p));
}

/// A bound AppState on images/checker.png with its cage; jobs run inline (synchronous worker).
/// The Bind panel holds the session's parameters (spacing fixed, not automatic), so the tests'
/// re-binds (cancel, line edits) work at the same coarse spacing as the session.
inline std::unique_ptr<ui::AppState> boundState(double spacing = 10.0) {
  auto state = std::make_unique<ui::AppState>();
  state->worker.setSynchronous(true);
  const std::string dir = std::string(KC_SOURCE_DIR) + "/images/";
  state->source = app::loadImage(dir + "checker.png");
  state->imagePath = dir + "checker.png";
  auto s = boundChecker(dir, state->source.width, state->source.height, spacing);
  ui::installSession(*state, s, ui::buildDisplayMesh(*s, app::warpMeshOptionsFor(*s, OutsideMode::Pinned)),
                     /*fromOptimizer=*/true);
  state->bindParams = s->params;
  state->autoSpacing = false;
  return state;
}

/// images/checker.png with its cage drawn and not bound (the draft cage); jobs run inline, binds
/// at a fixed `spacing`.
inline std::unique_ptr<ui::AppState> unboundChecker(double spacing) {
  auto s = std::make_unique<ui::AppState>();
  s->worker.setSynchronous(true);
  const std::string dir = std::string(KC_SOURCE_DIR) + "/images/";
  s->source = app::loadImage(dir + "checker.png");
  s->autoSpacing = false;
  s->bindParams.spacing = spacing;
  ui::setDraftCage(*s, app::loadCage(dir + "checker.cage.json"));
  return s;
}

/// A new document on a generated 400×300 picture with a background (scene_image.h), in the cage
/// tool with an empty cage; jobs run inline, binds at a fixed 10 px spacing.
inline std::unique_ptr<ui::AppState> newPicture() {
  auto s = std::make_unique<ui::AppState>();
  s->worker.setSynchronous(true);
  s->source = sceneImage(400, 300);
  s->sourceVersion.bump();
  Cage empty;
  empty.closed = false;
  ui::setDraftCage(*s, empty);
  s->tool = ui::Tool::Cage;
  s->bindParams.spacing = 10.0;
  return s;
}

/// Headless ImGui: a context with a display size and a built font atlas; frames run NewFrame →
/// draw → Render with no renderer backend.
class HeadlessImGui {
 public:
  HeadlessImGui() {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(1400, 900);
    io.DeltaTime = 1.0f / 60.0f;
    io.IniFilename = nullptr;
    // The key map of ImGui's GLFW backend (keys are GLFW codes, as in the window).
    io.KeyMap[ImGuiKey_Tab] = GLFW_KEY_TAB;
    io.KeyMap[ImGuiKey_LeftArrow] = GLFW_KEY_LEFT;
    io.KeyMap[ImGuiKey_RightArrow] = GLFW_KEY_RIGHT;
    io.KeyMap[ImGuiKey_Backspace] = GLFW_KEY_BACKSPACE;
    io.KeyMap[ImGuiKey_Enter] = GLFW_KEY_ENTER;
    io.KeyMap[ImGuiKey_Escape] = GLFW_KEY_ESCAPE;
    io.KeyMap[ImGuiKey_KeyPadEnter] = GLFW_KEY_KP_ENTER;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
  }
  ~HeadlessImGui() { ImGui::DestroyContext(); }
  template <class F>
  void frame(F&& draw) {
    ImGui::NewFrame();
    draw();
    ImGui::Render();
  }
  /// Clicks at screen point p over three frames (move, press, release), drawing with `draw`.
  template <class F>
  void click(const Vec2& p, F&& draw, int button = 0) {
    drag(p, p, draw, button, 0);
  }
  /// Presses `button` at a, moves to b in `steps` frames, releases there.
  template <class F>
  void drag(const Vec2& a, const Vec2& b, F&& draw, int button = 0, int steps = 6) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(float(a.x()), float(a.y()));
    frame(draw);
    io.MouseDown[button] = true;
    frame(draw);
    for (int k = 1; k <= steps; ++k) {
      const Vec2 p = a + (b - a) * (double(k) / steps);
      io.MousePos = ImVec2(float(p.x()), float(p.y()));
      frame(draw);
    }
    io.MouseDown[button] = false;
    frame(draw);
  }
  /// Hovers every widget marked in the last frame of `draw` (AppState::widgets) for two frames and
  /// returns the labels of those that showed no tooltip, quoted ("" when every one did).
  template <class F>
  std::string widgetsWithoutTooltip(ui::AppState& state, F&& draw) {
    const std::map<std::string, Vec2> widgets = state.widgets;
    std::string missing;
    for (const auto& [label, at] : widgets) {
      ImGui::GetIO().MousePos = ImVec2(float(at.x()), float(at.y()));
      frame(draw);
      frame(draw);
      const ImGuiWindow* tip = ImGui::FindWindowByName("##Tooltip_00");
      if (!tip || !tip->Active) missing += " '" + label + "'";
    }
    return missing;
  }
  /// Clicks the widget whose visible label is `label` (as the panels reported it in the last
  /// frame, AppState::widgets). Fails the test when no widget has that label.
  template <class F>
  void clickLabel(ui::AppState& state, const std::string& label, F&& draw) {
    const auto it = state.widgets.find(label);
    ASSERT_NE(it, state.widgets.end()) << "no widget labelled '" << label << "' in the last frame";
    click(it->second, draw);
  }
};

}  // namespace kc::test
