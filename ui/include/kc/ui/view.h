#pragma once
/// The canvas view: where the image sits on screen (pan) and how large (zoom). Pure math, no GL.

#include "kc/core/types.h"

namespace kc::ui {

/// Maps image pixels (x right, y down) to screen pixels: s = canvasMin + offset + zoom·p.
struct View {
  Vec2 canvasMin = Vec2::Zero();        ///< Top-left of the canvas on screen.
  Vec2 canvasSize = Vec2(1.0, 1.0);     ///< Canvas extent on screen.
  Vec2 offset = Vec2::Zero();           ///< Screen position of image point (0, 0) relative to canvasMin.
  double zoom = 1.0;                    ///< Screen pixels per image pixel.
  bool fitted = false;                  ///< Set by fit(), cleared by zoom and pan (refit on resize).

  Vec2 toScreen(const Vec2& p) const { return canvasMin + offset + zoom * p; }
  Vec2 toImage(const Vec2& s) const { return (s - canvasMin - offset) / zoom; }
  bool containsScreen(const Vec2& s) const;

  /// Zooms by `factor` keeping the image point under screen point `s` fixed; zoom ∈ [1/64, 64].
  void zoomAt(const Vec2& s, double factor);
  /// Moves the picture by a screen-space delta.
  void pan(const Vec2& delta) {
    offset += delta;
    fitted = false;
  }
  /// Sets the zoom to `z` (1 = one screen pixel per image pixel) keeping the canvas centre fixed.
  void zoomTo(double z);
  /// Centres a width×height image in the canvas, as large as fits with `margin` (fraction) around.
  void fit(int width, int height, double margin = 0.04);
};

}  // namespace kc::ui
