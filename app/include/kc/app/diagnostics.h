#pragma once
/// The property table of a bound session (thesis Tables 6.1–6.4, with measured numbers) and its
/// locality statistics (LBC paper eq. 19–21). Shared by `kcwarp-cli stats` and the GUI.

#include <vector>

#include "kc/app/session.h"
#include "kc/core/metrics.h"

namespace kc::app {

/// What a person sees when dragging one control point: the pixels that follow a drag of
/// kDragPixels by at least kVisibleShift pixels, i.e. those where that control's weight is at least
/// kDragWeight (a pixel moves by w_i(x)·d under a translation d of control i).
inline constexpr double kDragPixels = 40.0;
inline constexpr double kVisibleShift = 0.5;
inline constexpr double kDragWeight = kVisibleShift / kDragPixels;  ///< 0.0125

/// The area that moves under a drag of one control (see kDragWeight), over points inside the cage
/// on a regular grid: per control, the fraction of the points where w_i ≥ kDragWeight.
struct DragArea {
  std::vector<double> fraction;  ///< Per control (m), in [0, 1] of the cage's area.
  double mean = 0.0;             ///< Mean of `fraction` over the controls.
  double max = 0.0;              ///< Largest `fraction`.
  Index maxControl = -1;         ///< The control with the largest (−1 when there are no points).
  double minWeight = 0.0;        ///< Deepest weight at the points (the negative lobes inside the cage).
  Index points = 0;              ///< Grid points inside the cage.
  int step = 2;                  ///< Grid step, pixels.
};

/// The drag area of the weights W (#P×m) at P grid points inside the cage, `step` px apart.
DragArea dragArea(const Weights& W, int step);

/// One property measured over a set of points.
struct PropertyRow {
  double partitionOfUnity = 0.0;  ///< max |Σ w_i − 1|
  double reproduction = 0.0;      ///< max |Σ w_i c_i − x|_∞, pixels
  double minWeight = 0.0;
  Index negatives = 0;            ///< weights < −1e-6
  Index points = 0;
};

struct Diagnostics {
  PropertyRow samples;   ///< W itself, at the samples.
  PropertyRow inside;    ///< w(x) at pixel centres inside the cage.
  PropertyRow image;     ///< w(x) at pixel centres over the whole image (empty when !outsideWeights).
  /// The field has weights outside the cage (BackendCapabilities::outsideCage). A mesh field (LBC)
  /// has none: its weights there are 0, so `image` would only measure that; it is left empty.
  double lagrange = 0.0;        ///< max |w_i(c_j) − δ_ij|
  double edgeLinearity = 0.0;   ///< max deviation from (4.7) at points along every cage edge and stick, every h/8
  double stickLinearity = 0.0;  ///< the same along the sticks only (edges on no closed loop; thesis Table 6.6)
  bool sticks = false;          ///< the cage has sticks (stickLinearity is measured)
  LocalityStats locality;       ///< inside the cage
  /// Area that moves ≥ kVisibleShift px under a kDragPixels drag of one control, inside the cage,
  /// on the pixel centres every max(2, pixelStep) px (a subset of the diagnostics grid).
  DragArea drag;
  /// Memory of the compact weights inside the cage (entries w > 10⁻³/m in CSR: 8 B value + 4 B
  /// column per entry, 4 B per row) over dense storage (8 B per entry), as in LBC paper Table 1.
  double compactFraction = 1.0;
  int pixelStep = 1;            ///< evaluation grid step in pixels
  double evalSeconds = 0.0;
  bool outsideWeights = true;
};

/// Measures every property of session.field (which must be ready) on a grid of pixel centres
/// with at most about maxPoints points.
Diagnostics diagnose(const Session& session, Index maxPoints = 250000);

}  // namespace kc::app
