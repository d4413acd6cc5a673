#include "kc/ui/tools/cage_tool.h"

#include <algorithm>
#include <string>
#include <utility>

#include "kc/ui/app_state.h"
#include "kc/ui/edits.h"

namespace kc::ui {
namespace {

Cage withPoints(const Points& C, bool closed) {
  Cage c = closed ? Cage::polygon(C) : Cage{};
  c.C = C;
  c.closed = closed;
  if (!closed) c.edges.clear();
  return c;
}

/// Inserts p before index i of the draft cage, as one undo entry; returns i.
Index addPoint(AppState& state, Index i, const Vec2& p) {
  const Cage before = state.cage;
  setDraftCage(state, cageWithInserted(state.cage, i, p));
  commitCage(state, before, "add cage point");
  return i;
}

}  // namespace

Cage cageWithout(const Cage& cage, Index i) {
  Points C(cage.size() - 1, 2);
  for (Index r = 0, k = 0; r < cage.size(); ++r)
    if (r != i) C.row(k++) = cage.C.row(r);
  // A closed cage with fewer than 3 points reopens so the user can keep adding points.
  return withPoints(C, cage.closed && C.rows() >= 3);
}

Cage cageWithInserted(const Cage& cage, Index i, const Vec2& p) {
  Points C(cage.size() + 1, 2);
  for (Index r = 0, k = 0; r <= cage.size(); ++r) {
    if (r == i) C.row(r) = p.transpose();
    else C.row(r) = cage.C.row(k++);
  }
  return withPoints(C, cage.closed);
}

Index nearestEdge(const Cage& cage, const Vec2& p, double radius) {
  const Index m = cage.size();
  if (!cage.closed || m < 2) return -1;
  Index best = -1;
  double bestDistance = radius;
  for (Index k = 0; k < m; ++k) {
    const Vec2 a = cage.C.row(k).transpose(), b = cage.C.row((k + 1) % m).transpose();
    const double t = std::clamp((p - a).dot(b - a) / std::max(1e-12, (b - a).squaredNorm()), 0.0, 1.0);
    const double d = (a + t * (b - a) - p).norm();
    if (d <= bestDistance) {
      bestDistance = d;
      best = k;
    }
  }
  return best;
}

void CageTool::press(AppState& state, const PointerEvent& e) {
  if (m_dragging >= 0) return;
  m_clickWhileDrawing = false;
  const Index hit = pickPoint(state.cage.C, e.position, e.pickRadius);
  const bool graph = cageIsEdgeGraph(state.cage);  // points move; adding or removing would lose its edges
  if (e.button == MouseButton::Right) {
    if (hit >= 0 && !graph) {
      const Cage before = state.cage;
      setDraftCage(state, cageWithout(state.cage, hit));
      commitCage(state, before, "delete cage point");
      m_selected = -1;
    }
    return;
  }
  if (e.button != MouseButton::Left) return;
  if (hit >= 0) {
    if (!cageComplete(state.cage) && hit == 0 && state.cage.size() >= 3) {  // close the polygon
      const Cage before = state.cage;
      setDraftCage(state, withPoints(state.cage.C, true));
      commitCage(state, before, "close cage");
      m_selected = hit;
      return;
    }
    m_dragging = m_selected = hit;
    m_before = state.cage;
    m_grab = e.position - state.cage.C.row(hit).transpose();
    m_moved = false;
    // Drawing a cage round a narrow gap puts the next point within the pick radius of one across
    // the gap: a click there (not a drag, not on the point itself) adds it (see release).
    m_clickSlop = 0.25 * e.pickRadius;
    m_clickWhileDrawing = !state.cage.closed && !graph && hit != 0;
    m_pressAt = e.position;
    return;
  }
  if (graph) return;
  if (!state.cage.closed) {
    m_selected = addPoint(state, state.cage.size(), e.position);
  } else {
    const Index k = nearestEdge(state.cage, e.position, 2.0 * e.pickRadius);
    if (k < 0) return;
    m_selected = addPoint(state, k + 1, e.position);
  }
  // Let the user keep dragging the point just added.
  m_dragging = m_selected;
  m_before = state.cage;
  m_grab = Vec2::Zero();
  m_moved = false;
}

void CageTool::drag(AppState& state, const PointerEvent& e) {
  if (m_dragging < 0 || m_dragging >= state.cage.size()) return;
  Cage c = state.cage;
  c.C.row(m_dragging) = (e.position - m_grab).transpose();
  m_moved = true;
  setDraftCage(state, std::move(c));
}

void CageTool::release(AppState& state, const PointerEvent& e) {
  if (m_dragging < 0) return;
  if (std::exchange(m_clickWhileDrawing, false) && (e.position - m_pressAt).norm() < m_clickSlop) {
    if (m_grab.norm() >= m_clickSlop) {  // beside the point: add one there
      setDraftCage(state, m_before);     // the pressed point stays where it was
      m_selected = addPoint(state, state.cage.size(), m_pressAt);
      m_dragging = -1;
      return;
    }
    // On the point itself: it is selected. A click meant to add a point right beside it (an outline
    // a pixel or two from itself) lands there too when the view is zoomed out: say so.
    if (!m_moved)
      postMessage(state,
                  "Point " + std::to_string(m_dragging) +
                      " selected: the click was on it. To add a point this close, zoom in (mouse wheel).",
                  false);
  }
  drag(state, e);
  if (m_moved && !(m_before.C.rows() == state.cage.C.rows() && m_before.C == state.cage.C)) commitCage(state, m_before, "move cage point");
  m_dragging = -1;
}

void CageTool::cancel(AppState& state) {
  if (m_dragging >= 0 && m_moved) setDraftCage(state, m_before);
  m_dragging = -1;
  m_clickWhileDrawing = false;
}

void CageTool::deleteSelected(AppState& state) {
  if (m_selected < 0 || m_selected >= state.cage.size() || cageIsEdgeGraph(state.cage)) return;
  const Cage before = state.cage;
  setDraftCage(state, cageWithout(state.cage, m_selected));
  commitCage(state, before, "delete cage point");
  m_selected = -1;
}

}  // namespace kc::ui
