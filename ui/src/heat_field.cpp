#include "kc/ui/heat_field.h"

#include <algorithm>
#include <cmath>

#include "kc/app/heatmap.h"

namespace kc::ui {

std::vector<double> controlWeights(const Weights& W, Index control) {
  std::vector<double> w(static_cast<std::size_t>(W.rows()), 0.0);
  if (control < 0 || control >= W.cols()) return w;
  for (Index v = 0; v < W.rows(); ++v) w[static_cast<std::size_t>(v)] = W(v, control);
  return w;
}

double heatPosition(double v, const HeatRange& r) {
  if (r.log) {
    const double lo = std::log10(r.low), hi = std::log10(r.high);
    return v <= r.low ? 0.0 : std::clamp((std::log10(v) - lo) / std::max(1e-12, hi - lo), 0.0, 1.0);
  }
  return std::clamp((v - r.low) / std::max(1e-12, r.high - r.low), 0.0, 1.0);
}

std::vector<Rgba> heatColors(const std::vector<double>& w, bool log, double logFloor, HeatRange& range) {
  double lo = 0.0, hi = 1e-12;
  for (double v : w) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  range.log = log;
  if (log) {
    range.low = logFloor;
    range.high = std::max(hi, logFloor * 10.0);
  } else {
    range.low = lo;
    range.high = hi;
  }
  std::vector<Rgba> colors(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double t = heatPosition(w[i], range);
    colors[i] = app::heatColor(t);
    // Fade the bottom of the scale so the picture stays readable where the weight is ~0.
    colors[i].a = static_cast<std::uint8_t>(std::lround(255.0 * (0.3 + 0.7 * t)));
  }
  return colors;
}

}  // namespace kc::ui
