#include "kc/ui/canvas.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cmath>

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
        const Index hit = pickPoint(posedControls(state.boundCage.C, state.pose), e.position, e.pickRadius);
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
  if (mouseValid) state.mouseImage = state.view.toImage(mouse);
  const double pickRadius = 9.0 / state.view.zoom;
  auto event = [&](MouseButton b) {
    PointerEvent e;
    e.position = toolPosition(state, state.mouseImage);
    e.button = b;
    e.shift = io.KeyShift;
    e.ctrl = io.KeyCtrl;
    e.pickRadius = pickRadius;
    return e;
  };

  if (drag.button >= 0) {  // a drag that started on the canvas follows the mouse everywhere
    if (drag.panning) {
      state.view.pan(mouse - drag.lastScreen);
    } else if (mouse != drag.lastScreen) {
      dispatch(state, event(static_cast<MouseButton>(drag.button)), 1);
    }
    drag.lastScreen = mouse;
    if (!io.MouseDown[drag.button]) {
      if (!drag.panning) dispatch(state, event(static_cast<MouseButton>(drag.button)), 2);
      drag.button = -1;
      drag.panning = false;
    }
    return;
  }
  if (!state.canvasHovered) return;
  if (io.MouseWheel != 0.0f) state.view.zoomAt(mouse, std::pow(1.15, io.MouseWheel));
  for (int b = 0; b < 3; ++b) {
    if (!ImGui::IsMouseClicked(b)) continue;
    drag.button = b;
    drag.lastScreen = mouse;
    drag.panning = b == 2 || (b == 0 && ImGui::IsKeyDown(GLFW_KEY_SPACE));
    if (!drag.panning) dispatch(state, event(static_cast<MouseButton>(b)), 0);
    break;
  }
}

}  // namespace kc::ui
