#include "kc/ui/tools/line_tool.h"

#include <algorithm>

#include "kc/ui/app_state.h"
#include "kc/ui/line_edits.h"

namespace kc::ui {

void LineTool::press(AppState& state, const PointerEvent& e) {
  m_pressed = true;
  const int hit = pickLine(state.lines, e.position, e.pickRadius);
  if (e.button == MouseButton::Right) {
    m_pressed = false;
    if (m_drawing) {
      cancel(state);
      return;
    }
    if (hit >= 0) {
      state.lineSelection = {hit};
      deleteSelectedLines(state);
    }
    return;
  }
  if (e.button != MouseButton::Left) return;
  if (m_drawing) {  // the second click of click-click drawing
    m_startedByPress = false;
    finish(state, e.position);
    return;
  }
  if (hit >= 0) {
    auto& sel = state.lineSelection;
    const auto it = std::find(sel.begin(), sel.end(), hit);
    if (!e.shift) sel = {hit};
    else if (it == sel.end()) sel.push_back(hit);
    else sel.erase(it);
    m_pressed = false;
    return;
  }
  if (!e.shift) state.lineSelection.clear();
  m_drawing = true;
  m_startedByPress = true;
  m_start = e.position;
}

void LineTool::drag(AppState&, const PointerEvent&) {}

void LineTool::release(AppState& state, const PointerEvent& e) {
  const bool pressed = m_pressed;
  m_pressed = false;
  if (!pressed || !m_drawing || !m_startedByPress) return;
  m_startedByPress = false;
  // A press and release close together is a click: the line ends at the next click.
  if ((e.position - m_start).norm() > 2.0 * e.pickRadius) finish(state, e.position);
}

void LineTool::cancel(AppState&) {
  m_drawing = false;
  m_pressed = false;
  m_startedByPress = false;
}

void LineTool::finish(AppState& state, const Vec2& end) {
  m_drawing = false;
  app::Structure after = state.lines;
  StructureLine l;
  l.a = m_start;
  l.b = end;
  after.lines.push_back(l);
  if (editLines(state, std::move(after), "add line")) state.lineSelection = {static_cast<int>(state.lines.lines.size()) - 1};
}

}  // namespace kc::ui
