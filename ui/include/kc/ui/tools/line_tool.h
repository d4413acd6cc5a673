#pragma once
/// Line tool (thesis 5.3): draws the structure lines kept straight and parallel. Press and drag
/// on the picture draws a line from the press to the release; a click without dragging starts a
/// line and a second click ends it. A click on a line selects it (Shift adds or removes it), a drag
/// that starts on one draws a new line (two lines drawn a few pixels apart), a right-click on a
/// line deletes it. An end drawn a little past the cage's outline (within the pick radius) is
/// moved back onto it. Every change goes through editLines (line_edits.h): it is
/// validated against the cage (refused with the reason), recorded for undo, and re-binds.

#include "kc/core/types.h"
#include "kc/ui/tools/pointer.h"

namespace kc::ui {

struct AppState;

class LineTool {
 public:
  void press(AppState& state, const PointerEvent& e);
  void drag(AppState& state, const PointerEvent& e);
  void release(AppState& state, const PointerEvent& e);
  /// Forgets a line being drawn.
  void cancel(AppState& state);

  /// A line is being drawn: it starts at start() (image pixels, rest picture).
  bool drawing() const { return m_drawing; }
  Vec2 start() const { return m_start; }
  /// True between press and release (a drag is in progress).
  bool active() const { return m_pressed; }

 private:
  void finish(AppState& state, const Vec2& end);
  bool m_drawing = false;
  bool m_pressed = false;
  bool m_startedByPress = false;  ///< This press started the line (its release may end it).
  int m_pressedLine = -1;         ///< The line the press was on: selected if the release is a click.
  bool m_shift = false;           ///< Shift held at the press.
  double m_pickRadius = 8.0;      ///< The press's pick radius (image pixels): how far an end may overshoot the cage.
  Vec2 m_start = Vec2::Zero();
};

}  // namespace kc::ui
