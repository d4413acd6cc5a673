#pragma once
/// Pose tool (thesis 6.3.3): left-drag a control point to translate it, right-drag to rotate it
/// about its rest position; shift-click toggles selection; left-drag on empty canvas selects with a
/// rectangle; dragging a selected point moves the whole selection. Right-dragging a point of a
/// multi-selection, or off the points, turns the whole selection about its pivot (the selection's
/// centre unless the user dragged the pivot marker elsewhere). One undo entry per drag.

#include <vector>

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
  bool rotating() const { return m_mode == Mode::Rotate || m_mode == Mode::RotateGroup; }
  /// While rotating(): the angle turned so far (radians, counter-clockwise on screen).
  double angle() const { return m_angle; }
  /// Corners of the selection rectangle (image pixels) while selectingRect().
  Vec2 rectStart() const { return m_start; }
  Vec2 rectEnd() const { return m_current; }

 private:
  enum class Mode { None, Move, Rotate, RotateGroup, MovePivot, Select };
  Mode m_mode = Mode::None;
  Vec2 m_start = Vec2::Zero(), m_current = Vec2::Zero();
  Pose m_before;
  Index m_pivot = -1;        ///< Control under the mouse at press.
  Vec2 m_groupPivot = Vec2::Zero();  ///< RotateGroup: the centre of the turn (posed image pixels).
  double m_startAngle = 0.0;
  double m_angle = 0.0;      ///< Rotation: the angle turned so far.
  bool m_angleSet = false;   ///< Rotation: reference direction known.
  bool m_additive = false;   ///< Shift held at press (rectangle adds to the selection).
};

/// Angle of d in screen axes, counter-clockwise on screen (y down): atan2(−d.y, d.x).
double screenAngle(const Vec2& d);

/// The pivot of a multi-selection (posed image pixels): AppState::pivot when the user moved it,
/// else the mean of the selected points' posed positions. Meaningful for ≥ 2 selected points.
Vec2 selectionPivot(const AppState& state);

/// `before` with the handles in `selection` turned by `angle` (counter-clockwise on screen) about
/// `pivot`: each handle's map x ↦ R_θ(x − c) + c + t becomes x ↦ R_α(R_θ(x − c) + c + t − p) + p,
/// i.e. θ' = θ + α and t' = R_α(c + t − p) + p − c (R = screenRotation, c the rest position).
Pose rotateAbout(const Pose& before, const Points& C, const std::vector<Index>& selection, const Vec2& pivot, double angle);

}  // namespace kc::ui
