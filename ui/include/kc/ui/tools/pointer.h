#pragma once
/// What a tool sees of the mouse: position in image pixels, button, modifiers. Tools never read
/// ImGui or GLFW, so their logic runs in tests without a window.

#include "kc/core/types.h"

namespace kc::ui {

enum class MouseButton { Left = 0, Right = 1, Middle = 2 };

struct PointerEvent {
  Vec2 position = Vec2::Zero();        ///< Image pixels (x right, y down).
  MouseButton button = MouseButton::Left;
  bool shift = false, ctrl = false;
  double pickRadius = 8.0;             ///< How close counts as "on" a point, in image pixels.
};

/// Index of the row of P (#P×2) nearest to p within `radius`, or −1.
Index pickPoint(const Points& P, const Vec2& p, double radius);

}  // namespace kc::ui
