#pragma once
/// Cage tool: click on empty canvas to add a point (while the polygon is open), click the first
/// point to close it, click near an edge of a closed cage to insert a point, drag a point to move
/// it, right-click a point (or Delete) to remove it. While the polygon is open, a click (no drag)
/// within the pick radius of a point other than the first, but not on it, adds a point too: the
/// other side of a gap a few pixels wide can be drawn without zooming in. Each edit is one undo entry; the draft cage
/// is validated after every change (AppState::cageStatus).

#include "kc/core/cage.h"
#include "kc/ui/tools/pointer.h"

namespace kc::ui {

struct AppState;

class CageTool {
 public:
  void press(AppState& state, const PointerEvent& e);
  void drag(AppState& state, const PointerEvent& e);
  void release(AppState& state, const PointerEvent& e);
  void cancel(AppState& state);
  /// Removes the selected point (Delete key).
  void deleteSelected(AppState& state);

  bool active() const { return m_dragging >= 0; }
  /// Last clicked point of the draft cage, or −1.
  Index selected() const { return m_selected; }

 private:
  Index m_dragging = -1;
  Index m_selected = -1;
  bool m_moved = false;
  Vec2 m_grab = Vec2::Zero();
  Cage m_before;
  /// This press, while drawing, is on a point other than the first: not dragged, it adds a point at
  /// m_pressAt when it is beside the point (m_grab at least m_clickSlop), else says it selected it.
  bool m_clickWhileDrawing = false;
  Vec2 m_pressAt = Vec2::Zero();
  double m_clickSlop = 0.0;       ///< How far (image pixels) a click may move and stay a click.
};

/// The draft cage after removing point i (a closed cage stays a closed polygon).
Cage cageWithout(const Cage& cage, Index i);
/// The draft cage with p inserted before index i (i = size() appends).
Cage cageWithInserted(const Cage& cage, Index i, const Vec2& p);
/// The edge (k, k+1 mod m) of a closed cage nearest to p within radius, as k; −1 when none.
Index nearestEdge(const Cage& cage, const Vec2& p, double radius);

}  // namespace kc::ui
