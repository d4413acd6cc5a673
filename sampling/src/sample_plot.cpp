#include "kc/sampling/sample_plot.h"

#include <algorithm>

namespace kc::sampling {

Rgb kindColor(SampleKind kind) {
  switch (kind) {
    case SampleKind::Control: return {0, 0, 0};
    case SampleKind::Edge: return {220, 30, 30};
    case SampleKind::Line: return {240, 140, 0};
    case SampleKind::Interior: return {30, 60, 220};
    case SampleKind::Exterior: return {30, 150, 60};
  }
  return {128, 128, 128};
}

std::vector<PlotDot> samplePlot(const SampleSet& S, double h) {
  const double r = std::max(1.0, 0.2 * h);
  auto layer = [](SampleKind k) {
    return k == SampleKind::Control ? 2 : (k == SampleKind::Edge || k == SampleKind::Line) ? 1 : 0;
  };
  std::vector<PlotDot> dots;
  dots.reserve(static_cast<std::size_t>(S.size()));
  for (int l = 0; l <= 2; ++l)
    for (Index i = 0; i < S.size(); ++i) {
      const SampleKind k = S.kind[static_cast<std::size_t>(i)];
      if (layer(k) != l) continue;
      dots.push_back({S.X(i, 0), S.X(i, 1), k == SampleKind::Control ? 2.0 * r : r, kindColor(k)});
    }
  return dots;
}

}  // namespace kc::sampling
