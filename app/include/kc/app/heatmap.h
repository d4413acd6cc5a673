#pragma once
/// Pictures of weights and cages: the weight of one control point over the image with a colour
/// bar (like thesis Figs 6.1–6.2), and overlays of the cage, the deformed cage and the samples.

#include <functional>
#include <span>
#include <string>

#include "kc/app/session.h"
#include "kc/core/cage.h"
#include "kc/core/rasterize.h"
#include "kc/core/types.h"

namespace kc::app {

enum class HeatScale { Linear, Log };

}  // namespace kc::app

template <>
struct kc::EnumNames<kc::app::HeatScale> {
  static constexpr std::array<std::pair<app::HeatScale, std::string_view>, 2> table{
      {{app::HeatScale::Linear, "linear"}, {app::HeatScale::Log, "log"}}};
};

namespace kc::app {

struct HeatmapOptions {
  HeatScale scale = HeatScale::Linear;
  double logFloor = 1e-4;   ///< Log scale: values ≤ floor (and negatives) get the bottom colour.
  /// Linear range; when min ≥ max the range is automatic: [min(0, w_min), max(w_max, 1e-12)].
  double minValue = 0.0, maxValue = 0.0;
  int gridStep = 2;         ///< w is evaluated every gridStep pixels and bilinearly interpolated.
  bool colorBar = true;     ///< Adds a bar with ticks to the right (output is wider).
  bool drawCage = true;     ///< Cage polygon and control points on top; the shown control ringed.
};

/// What a heatmap was made of (for reports and tests).
struct HeatmapReport {
  double minValue = 0.0, maxValue = 0.0;  ///< Range of w_i over the evaluated grid.
  double lowEnd = 0.0, highEnd = 0.0;     ///< Values at the bottom and top of the colour bar.
  Index points = 0;                       ///< Points where w was evaluated.
};

/// Weights of points P (#P×2) → #P×m; e.g. CoordinateField::weightsAt.
using WeightFunction = std::function<Weights(const Points&)>;

/// Colour map (a piecewise-linear viridis): t ∈ [0, 1] (clamped) → opaque colour.
Rgba heatColor(double t);

/// w_control over a width×height image, coloured by `options`; the cage (may be empty) is drawn
/// on top. Throws std::invalid_argument for a bad control index or size.
Image weightHeatmap(const WeightFunction& weightsAt, const Cage& cage, int width, int height, Index control,
                    const HeatmapOptions& options = {}, HeatmapReport* report = nullptr);
/// Same for a bound session's field.
Image weightHeatmap(const Session& session, Index control, const HeatmapOptions& options = {},
                    HeatmapReport* report = nullptr);

/// Colours a scalar field V (h×w, one value per pixel) with a colour bar titled `title`.
Image colorizeField(const RowMatrix& V, const HeatmapOptions& options, const std::string& title,
                    HeatmapReport* report = nullptr);

struct OverlayStyle {
  Rgba restCage{70, 70, 90, 255};
  Rgba deformedCage{255, 140, 0, 255};
  Rgba line{230, 0, 230, 255};  ///< Structure lines (deformed), magenta like line samples.
  Rgba rigid{0, 200, 220, 255}; ///< Rigid regions' outlines (deformed), cyan.
  int thickness = 1;
  int pointRadius = 3;       ///< Control points (0 = none).
  int sampleRadius = 1;
};

/// Colour of a sample kind in overlays: control red, edge orange, line magenta, interior blue,
/// exterior grey.
Rgba sampleColor(SampleKind kind);

/// Draws the closed or open cage polygon with its control points (highlight ≥ 0: that control
/// ringed) into `image`. Points are in pixel coordinates of the image.
void drawCage(Image& image, const Cage& cage, Rgba color, const OverlayStyle& style = {}, Index highlight = -1);
/// Draws the cage with its control points moved to P (m×2, e.g. posedControls).
void drawDeformedCage(Image& image, const Cage& cage, const Points& P, const OverlayStyle& style = {});
/// Draws the session's structure as the pose deforms it: each line through 65 points along it,
/// and each rigid region's polygon through 16 points per edge, moved by the field
/// (deformPoints), so a bent line or a squeezed region shows as it is.
void drawDeformedLines(Image& image, const Session& session, const Pose& pose, const OverlayStyle& style = {});
/// The same for `lines` (the session's own or others, e.g. to show how a session without them bends them).
void drawDeformedLines(Image& image, const Session& session, std::span<const StructureLine> lines, const Pose& pose,
                       const OverlayStyle& style = {});
/// Draws sample points coloured by kind.
void drawSamples(Image& image, const SampleSet& samples, const OverlayStyle& style = {});

}  // namespace kc::app
