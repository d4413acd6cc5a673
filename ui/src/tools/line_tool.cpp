#include "kc/ui/tools/line_tool.h"

#include <algorithm>
#include <utility>

#include "kc/core/cage.h"
#include "kc/ui/app_state.h"
#include "kc/ui/line_edits.h"

namespace kc::ui {
namespace {

/// The end b of the line a → b moved back onto the cage edge it overshoots, when a is inside the
/// cage, b outside, and the first edge the line crosses is at most `reach` from b (a line drawn up
/// to the outline that went a little past it); else b unchanged.
Vec2 endOnTheCage(const Cage& cage, const Vec2& a, const Vec2& b, double reach) {
  if (!insideCage(cage, a) || insideCage(cage, b)) return b;
  const Vec2 d = b - a;
  double first = 1.0;  // the smallest t in (0, 1] where a + t·d meets an edge
  for (const auto& [i, j] : loopEdges(cage)) {  // the outline (sticks lie inside)
    const Vec2 p = cage.C.row(i).transpose(), e = Vec2(cage.C.row(j).transpose()) - p;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (den == 0.0) continue;  // parallel
    const Vec2 ap = p - a;
    const double t = (ap.x() * e.y() - ap.y() * e.x()) / den, u = (ap.x() * d.y() - ap.y() * d.x()) / den;
    if (t > 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0) first = std::min(first, t);
  }
  return (1.0 - first) * d.norm() <= reach ? Vec2(a + first * d) : b;
}

}  // namespace

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
  // On a line: a click selects it (at the release), a drag draws a new line from here (two lines
  // drawn a few pixels apart start on each other's pick radius).
  m_pressedLine = hit;
  m_shift = e.shift;
  if (hit < 0 && !e.shift) state.lineSelection.clear();
  m_drawing = true;
  m_startedByPress = true;
  m_start = e.position;
  m_pickRadius = e.pickRadius;
}

void LineTool::drag(AppState&, const PointerEvent&) {}

void LineTool::release(AppState& state, const PointerEvent& e) {
  const bool pressed = m_pressed;
  m_pressed = false;
  if (!pressed || !m_drawing || !m_startedByPress) return;
  m_startedByPress = false;
  const bool dragged = (e.position - m_start).norm() > 2.0 * e.pickRadius;
  const int line = std::exchange(m_pressedLine, -1);
  if (line >= 0 && !dragged) {  // a click on a line selects it (Shift: adds or removes it)
    m_drawing = false;
    auto& sel = state.lineSelection;
    const auto it = std::find(sel.begin(), sel.end(), line);
    if (!m_shift) sel = {line};
    else if (it == sel.end()) sel.push_back(line);
    else sel.erase(it);
    return;
  }
  if (line >= 0 && !m_shift) state.lineSelection.clear();
  // A press and release close together is a click: the line ends at the next click.
  if (dragged) finish(state, e.position);
}

void LineTool::cancel(AppState&) {
  m_drawing = false;
  m_pressedLine = -1;
  m_pressed = false;
  m_startedByPress = false;
}

void LineTool::finish(AppState& state, const Vec2& end) {
  m_drawing = false;
  app::Structure after = state.lines;
  // An end drawn a little past the outline (within the pick radius) ends on it: a graded bind takes
  // a line ending on the cage, and no one can place an end exactly on an edge by hand.
  StructureLine l;
  l.a = endOnTheCage(state.cage, end, m_start, m_pickRadius);
  l.b = endOnTheCage(state.cage, l.a, end, m_pickRadius);
  after.lines.push_back(l);
  if (editLines(state, std::move(after), "add line")) state.lineSelection = {static_cast<int>(state.lines.lines.size()) - 1};
}

}  // namespace kc::ui
