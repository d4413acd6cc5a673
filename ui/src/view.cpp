#include "kc/ui/view.h"

#include <algorithm>

namespace kc::ui {

bool View::containsScreen(const Vec2& s) const {
  return s.x() >= canvasMin.x() && s.y() >= canvasMin.y() && s.x() < canvasMin.x() + canvasSize.x() &&
         s.y() < canvasMin.y() + canvasSize.y();
}

void View::zoomAt(const Vec2& s, double factor) {
  const Vec2 p = toImage(s);
  zoom = std::clamp(zoom * factor, 1.0 / 64.0, 64.0);
  offset = s - canvasMin - zoom * p;
  fitted = false;
}

void View::zoomTo(double z) {
  const Vec2 s = canvasMin + 0.5 * canvasSize, p = toImage(s);
  zoom = std::clamp(z, 1.0 / 64.0, 64.0);
  offset = s - canvasMin - zoom * p;
  fitted = false;
}

void View::fit(int width, int height, double margin) {
  if (width <= 0 || height <= 0) return;
  const double usable = 1.0 - 2.0 * margin;
  zoom = std::clamp(std::min(canvasSize.x() * usable / width, canvasSize.y() * usable / height), 1.0 / 64.0, 64.0);
  offset = 0.5 * (canvasSize - zoom * Vec2(width, height));
  fitted = true;
}

}  // namespace kc::ui
