#pragma once
/// Colours of one control's weights at the warp mesh vertices (the heatmap overlay drawn by the
/// renderer over the deformed picture), with app::heatColor's colour map. The weights are the
/// coordinate field's own (E(P)·Coef at the vertices, the numbers `kcwarp-cli warp --heatmap`
/// shows), not the mesh's thresholded copy used for deforming.

#include <vector>

#include "kc/core/rasterize.h"
#include "kc/core/types.h"

namespace kc::ui {

struct HeatRange {
  double low = 0.0, high = 1.0;  ///< Values at the bottom and top of the colour bar.
  bool log = false;
};

/// Column `control` of the field's vertex weights W (#V×m): #V values (zeros for a bad control).
std::vector<double> controlWeights(const Weights& W, Index control);

/// Colour per value: linear over [min(0, w_min), max(w_max, 1e-12)], or log10 over
/// [floor, max(w_max, floor·10)] (values ≤ floor get the bottom colour). Alpha grows from 30 %
/// at the bottom of the scale to 100 % at the top, so zero weights barely tint the picture.
/// Fills `range`.
std::vector<Rgba> heatColors(const std::vector<double>& w, bool log, double logFloor, HeatRange& range);

/// Position in [0, 1] of value v on the colour bar of `range`.
double heatPosition(double v, const HeatRange& range);

}  // namespace kc::ui
