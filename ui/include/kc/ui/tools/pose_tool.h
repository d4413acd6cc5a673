#pragma once
/// Pose tool (thesis 6.3.3): left-drag a control point to translate it, right-drag to rotate it
/// about its rest position; shift-click toggles selection; left-drag on empty canvas selects with a
/// rectangle; dragging a selected point moves the whole selection. One undo entry per drag.

#include "kc/core/deform.h"
#include "kc/ui/tools/pointer.h"

namespace kc::ui {

struct AppState;

class PoseTool {
 public:
  void press(AppState& state, const PointerEvent& e);
  void drag(AppState& state, const PointerEvent& e);
  void release(AppState& state, const PointerEvent& e);
  /// Abandons a drag, restoring the pose it started from.
  void cancel(AppState& state);

  bool active() const { return m_mode != Mode::None; }
  bool selectingRect() const { return m_mode == Mode::Select; }
  bool rotating() const { return m_mode == Mode::Rotate; }
  /// Corners of the selection rectangle (image pixels) while selectingRect().
  Vec2 rectStart() const { return m_start; }
  Vec2 rectEnd() const { return m_current; }

 private:
  enum class Mode { None, Move, Rotate, Select };
  Mode m_mode = Mode::None;
  Vec2 m_start = Vec2::Zero(), m_current = Vec2::Zero();
  Pose m_before;
  Index m_pivot = -1;        ///< Control under the mouse at press.
  double m_startAngle = 0.0;
  bool m_angleSet = false;   ///< Rotation: reference direction known.
  bool m_additive = false;   ///< Shift held at press (rectangle adds to the selection).
};

/// Angle of d in screen axes, counter-clockwise on screen (y down): atan2(−d.y, d.x).
double screenAngle(const Vec2& d);

}  // namespace kc::ui
