#pragma once
/// Weight brush: a stroke changes the target weights W0 (column of the active control) of the
/// samples under it with a smooth falloff; on release only those samples are re-optimized with
/// the current method (kc::app::reoptimize with the subset), on the worker thread.

#include <algorithm>
#include <cmath>
#include <vector>

#include "kc/core/types.h"
#include "kc/ui/tools/pointer.h"

namespace kc::ui {

struct AppState;

/// Smooth falloff of the brush: (1 − (d/r)²)² for d < r, else 0.
double brushFalloff(double distance, double radius);

/// One dab: for every paintable sample (interior, exterior, line — control and edge samples are
/// fixed by the optimizer) within `radius` of `centre`, adds amount·falloff to W0(s, control),
/// clamps it to [0, 1] and rescales the other entries of the row so it still sums to 1.
/// Marks touched samples in `painted` (#S flags). Returns the number of samples touched.
Index paintDab(Weights& W0, const SampleSet& samples, Index control, const Vec2& centre, double radius, double amount,
               std::vector<char>& painted);

/// The dabs of a stroke segment, shared by the weight and rigidity brushes: calls dab(c) at every
/// max(1, radius/4) pixels from `from` toward `to` (not at `from`, which had its dab) and returns
/// the last centre (`from` when the segment is shorter than one step).
template <class Dab>
Vec2 dabsAlong(const Vec2& from, const Vec2& to, double radius, Dab&& dab) {
  const double step = std::max(1.0, 0.25 * radius);
  const double length = (to - from).norm();
  const int n = static_cast<int>(std::floor(length / step));
  for (int k = 1; k <= n; ++k) dab(Vec2(from + (to - from) * (k * step / length)));
  return n > 0 ? Vec2(from + (to - from) * (n * step / length)) : from;
}

class BrushTool {
 public:
  void press(AppState& state, const PointerEvent& e);
  void drag(AppState& state, const PointerEvent& e);
  /// Ends the stroke and starts the re-optimization of the painted samples.
  void release(AppState& state, const PointerEvent& e);
  /// Abandons a stroke, restoring W0.
  void cancel(AppState& state);

  bool active() const { return m_active; }
  /// Samples touched by the current stroke (#S flags).
  const std::vector<char>& painted() const { return m_painted; }

 private:
  void dabsTo(AppState& state, const Vec2& p);

  bool m_active = false;
  bool m_subtract = false;
  Vec2 m_last = Vec2::Zero();
  Weights m_W0Before;
  std::vector<char> m_painted;
};

}  // namespace kc::ui
