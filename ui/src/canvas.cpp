#include "kc/ui/canvas.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <cmath>
#include <utility>
#include <vector>

#include "kc/ui/edits.h"

namespace kc::ui {
namespace {

Vec2 toVec(const ImVec2& v) { return {v.x, v.y}; }

/// The image-space position a tool works with: rest positions for the brushes on a warped picture.
Vec2 toolPosition(const AppState& state, const Vec2& image) {
  if ((state.tool == Tool::Brush || state.tool == Tool::Rigid) && showsWarp(state)) {
    Vec2 rest;
    if (restPositionOf(state.mesh, image, rest)) return rest;
  }
  return image;
}

void dispatch(AppState& state, const PointerEvent& e, int phase) {
  switch (state.tool) {
    case Tool::Pose:
      if (phase == 0) state.poseTool.press(state, e);
      else if (phase == 1) state.poseTool.drag(state, e);
      else state.poseTool.release(state, e);
      break;
    case Tool::Brush:
      if (phase == 0 && e.button == MouseButton::Right && state.bound) {  // right-click picks the painted control
        const Index hit = pickPoint(posedControls(state.bound->cage.C, state.pose), e.position, e.pickRadius);
        if (hit >= 0) state.activeControl = hit, state.selection = {hit}, state.pivot.reset();
        return;
      }
      if (phase == 0) state.brushTool.press(state, e);
      else if (phase == 1) state.brushTool.drag(state, e);
      else state.brushTool.release(state, e);
      break;
    case Tool::Rigid:
      if (phase == 0) state.rigidTool.press(state, e);
      else if (phase == 1) state.rigidTool.drag(state, e);
      else state.rigidTool.release(state, e);
      break;
    case Tool::Lines:
      if (phase == 0) state.lineTool.press(state, e);
      else if (phase == 1) state.lineTool.drag(state, e);
      else state.lineTool.release(state, e);
      break;
    case Tool::Cage:
      if (phase == 0) state.cageTool.press(state, e);
      else if (phase == 1) state.cageTool.drag(state, e);
      else state.cageTool.release(state, e);
      break;
  }
}

/// True when a press at screen point p belongs to the canvas: inside it, no popup open and no
/// ImGui window (panel, menu bar, dialog) there. ImGui's own test (WantCaptureMouse) is for the
/// mouse's position at the frame; a queued press may have happened elsewhere.
bool canvasAt(const AppState& state, const Vec2& p) {
  if (!state.view.containsScreen(p)) return false;
  const ImGuiContext& g = *ImGui::GetCurrentContext();
  if (g.OpenPopupStack.Size > 0) return false;
  const ImVec2 q(float(p.x()), float(p.y()));
  for (const ImGuiWindow* w : g.Windows)
    if ((w->Active || w->WasActive) && !w->Hidden && !w->IsFallbackWindow && !(w->Flags & ImGuiWindowFlags_NoMouseInputs) &&
        w->Rect().Contains(q))
      return false;
  return true;
}

/// The mouse as ImGui saw it this frame, as queued inputs (no window callbacks: the headless
/// tests): a press where ImGui saw one on the hovered canvas, a move, a release when the dragged
/// button is up.
std::vector<PointerInput> inputsFromImGui(const AppState& state) {
  const ImGuiIO& io = ImGui::GetIO();
  const Vec2 mouse = toVec(io.MousePos);
  std::vector<PointerInput> out;
  if (!ImGui::IsMousePosValid(&io.MousePos)) return out;
  const int held = state.canvasDrag.button;
  if (held >= 0) {
    out.push_back({PointerInput::Kind::Move, held, mouse, io.KeyShift, io.KeyCtrl});
    if (!io.MouseDown[held]) out.push_back({PointerInput::Kind::Release, held, mouse, io.KeyShift, io.KeyCtrl});
    return out;
  }
  if (!state.canvasHovered) return out;
  for (int b = 0; b < 3; ++b)
    if (ImGui::IsMouseClicked(b)) {
      out.push_back({PointerInput::Kind::Press, b, mouse, io.KeyShift, io.KeyCtrl});
      break;
    }
  return out;
}

}  // namespace

bool showsWarp(const AppState& state) {
  return state.bound && state.tool != Tool::Cage && state.tool != Tool::Lines && !state.showOriginal && state.mesh.hasWeights() && state.mesh.width() == state.source.width &&
         state.mesh.height() == state.source.height;
}

bool restPositionOf(const WarpMesh& mesh, const Vec2& p, Vec2& rest) {
  const Points& F = mesh.deformedVertices();
  const Points& V = mesh.restVertices();
  const Triangles& T = mesh.triangles();
  bool found = false;
  for (const auto& t : T) {
    const Vec2 a = F.row(t[0]).transpose(), b = F.row(t[1]).transpose(), c = F.row(t[2]).transpose();
    if (p.x() < std::min({a.x(), b.x(), c.x()}) || p.x() > std::max({a.x(), b.x(), c.x()}) ||
        p.y() < std::min({a.y(), b.y(), c.y()}) || p.y() > std::max({a.y(), b.y(), c.y()}))
      continue;
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(det) < 1e-12) continue;
    const double l1 = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / det;
    const double l2 = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / det;
    const double l0 = 1.0 - l1 - l2;
    if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
    rest = l0 * V.row(t[0]).transpose() + l1 * V.row(t[1]).transpose() + l2 * V.row(t[2]).transpose();
    found = true;  // keep looking: the last triangle is drawn on top
  }
  return found;
}

void layoutCanvas(AppState& state, const Vec2& min, const Vec2& size) {
  const Vec2 newSize = size.cwiseMax(Vec2(1.0, 1.0));
  // Refit when the canvas changes size, unless the user has zoomed or panned since the last fit.
  if (newSize != state.view.canvasSize && state.view.fitted) state.fitPending = true;
  state.view.canvasMin = min;
  state.view.canvasSize = newSize;
  if (state.fitPending && !state.source.empty()) {
    state.view.fit(state.source.width, state.source.height);
    state.fitPending = false;
  }
}

void handleCanvasInput(AppState& state) {
  ImGuiIO& io = ImGui::GetIO();
  const Vec2 mouse = toVec(io.MousePos);
  const bool mouseValid = ImGui::IsMousePosValid(&io.MousePos);
  CanvasDrag& drag = state.canvasDrag;
  state.canvasHovered = mouseValid && !io.WantCaptureMouse && state.view.containsScreen(mouse);
  if (state.canvasHovered && io.MouseWheel != 0.0f && drag.button < 0) state.view.zoomAt(mouse, std::pow(1.15, io.MouseWheel));

  std::vector<PointerInput> inputs = std::exchange(state.pointerInputs, {});
  if (!state.pointerQueued) inputs = inputsFromImGui(state);
  for (const PointerInput& in : inputs) {
    const Vec2 previous = drag.lastScreen;
    state.mouseImage = state.view.toImage(in.screen);
    PointerEvent e;
    e.position = toolPosition(state, state.mouseImage);
    e.button = static_cast<MouseButton>(drag.button >= 0 ? drag.button : in.button);
    e.shift = in.kind == PointerInput::Kind::Move ? io.KeyShift : in.shift;
    e.ctrl = in.kind == PointerInput::Kind::Move ? io.KeyCtrl : in.ctrl;
    e.pickRadius = 9.0 / state.view.zoom;
    if (drag.button < 0) {  // a press on the canvas starts a drag; the rest is ImGui's
      if (in.kind != PointerInput::Kind::Press || !canvasAt(state, in.screen)) continue;
      drag.button = in.button;
      drag.lastScreen = in.screen;
      drag.panning = in.button == 2 || (in.button == 0 && ImGui::IsKeyDown(GLFW_KEY_SPACE));
      if (!drag.panning) dispatch(state, e, 0);
      continue;
    }
    // A drag that started on the canvas follows the mouse everywhere, until its button goes up.
    if (in.kind == PointerInput::Kind::Press) continue;
    if (in.kind == PointerInput::Kind::Release && in.button != drag.button) continue;
    drag.lastScreen = in.screen;
    if (drag.panning) state.view.pan(in.screen - previous);
    else if (in.screen != previous) dispatch(state, e, 1);
    if (in.kind == PointerInput::Kind::Release) {
      if (!drag.panning) dispatch(state, e, 2);
      drag.button = -1;
      drag.panning = false;
    }
  }
  // A release the queue did not carry (the window lost the button while unfocused) ends the drag.
  // GLFW's state, not ImGui's: ImGui is given the queued buttons a change per frame (feedMouse).
  if (state.pointerQueued && drag.button >= 0 && glfwGetCurrentContext() &&
      glfwGetMouseButton(glfwGetCurrentContext(), drag.button) != GLFW_PRESS) {
    state.pointerInputs.push_back({PointerInput::Kind::Release, drag.button, drag.lastScreen, io.KeyShift, io.KeyCtrl});
    handleCanvasInput(state);
    return;
  }
  if (mouseValid) state.mouseImage = state.view.toImage(mouse);
}

}  // namespace kc::ui
