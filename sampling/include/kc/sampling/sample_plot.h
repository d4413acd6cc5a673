#pragma once
/// What a picture of a sampling shows, as plain data (the app draws it with OpenCV): one dot per
/// sample, one colour per kind, as in the thesis's figures (edges red, free samples blue/green).

#include <cstdint>
#include <vector>

#include "kc/core/types.h"

namespace kc::sampling {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

/// Control black, edge red, line orange, interior blue, exterior green.
Rgb kindColor(SampleKind kind);

struct PlotDot {
  double x = 0.0, y = 0.0;   ///< sample position (pixels of the sampled image)
  double radius = 1.0;       ///< pixels
  Rgb color;
};

/// One dot per sample of S, radius ≈ h/5 (controls ×2), drawn free samples first, then edges,
/// then controls so the cage stays visible.
std::vector<PlotDot> samplePlot(const SampleSet& S, double h);

}  // namespace kc::sampling
