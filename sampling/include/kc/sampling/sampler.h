#pragma once
/// One entry point for sampling a cage and its image domain (what `bind` and `sample` call).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "kc/core/cage.h"
#include "kc/core/solve.h"
#include "kc/core/types.h"
#include "kc/sampling/boundary.h"
#include "kc/sampling/blue_noise.h"

namespace kc::sampling {

enum class SamplerKind { BlueNoise, Grid };

/// How far outside the cage the free samples go. The field's weights outside the cage are used
/// by the `deform` outside mode only (pinned takes the exterior from a harmonic extension on the
/// warp mesh, exterior_weights.h; fixed and transparent move the inside only), so the other modes
/// need the exterior only as far as it shapes the weights inside and on the cage.
enum class ExteriorExtent {
  Frame,  ///< The whole image rectangle plus its margin (what `deform` needs).
  Band,   ///< The cage's bounding box grown by a band (SamplingOptions::band) on every side, within the frame.
};

}  // namespace kc::sampling

template <>
struct kc::EnumNames<kc::sampling::SamplerKind> {
  static constexpr std::array<std::pair<sampling::SamplerKind, std::string_view>, 2> table{
      {{sampling::SamplerKind::BlueNoise, "blue-noise"}, {sampling::SamplerKind::Grid, "grid"}}};
};

template <>
struct kc::EnumNames<kc::sampling::ExteriorExtent> {
  static constexpr std::array<std::pair<sampling::ExteriorExtent, std::string_view>, 2> table{
      {{sampling::ExteriorExtent::Frame, "frame"}, {sampling::ExteriorExtent::Band, "band"}}};
};

namespace kc::sampling {

/// Upper bound on the number of samples of one sampling: beyond it `sample` throws
/// std::invalid_argument naming the spacing that would fit.
inline constexpr Index kMaxSamples = 400000;

/// Width of the automatic exterior band in sample spacings (σ ≈ 0.95 h, so ≈ 6.3 σ, beyond the
/// kernel's 5σ cut-off): the weights inside and on the cage change less than a change of seed
/// does (docs/notes/big-pictures.md).
inline constexpr double kExteriorBandSpacings = 6.0;

struct SamplingOptions {
  double spacing = 6.0;      ///< h: sample spacing in pixels (> 0).
  double width = 0.0;        ///< Image domain [0, width] × [0, height] in pixels.
  double height = 0.0;
  /// Margin around the image (pixels); < 0 = automatic (a few σ ≈ 3h, so coordinates stay
  /// accurate up to the image border, thesis Fig 3.1).
  double margin = -1.0;
  SamplerKind kind = SamplerKind::BlueNoise;
  /// How far outside the cage to sample (ExteriorExtent). Frame by default.
  ExteriorExtent exterior = ExteriorExtent::Frame;
  /// ExteriorExtent::Band: the band's width in pixels; < 0 = automatic (kExteriorBandSpacings·h).
  double band = -1.0;
  std::uint64_t seed = 1;
  /// Progress callback for long relaxations (fraction in [0, 1]); may be empty. Called on the
  /// calling thread, outside parallel loops: returning false throws kc::Cancelled.
  Progress progress;
  /// Blue noise: density and inverse mean shift parameters (λ, s, stopping rule); defaults
  /// derive from h. relax.spacing and relax.progress are taken from the fields above.
  BlueNoiseOptions blueNoise;
  /// Structure lines (thesis 5.3.3): sampled at spacing ≈ h and kept fixed; free samples keep
  /// their distance from them. Checked with validateLines.
  std::vector<StructureLine> lines;
  /// Graded sampling (blue noise only): the local spacing h(x) (featureSizing), whose hMax is
  /// `spacing`. Null or not graded(): the uniform sampling at `spacing`.
  std::shared_ptr<const SizingField> sizing;
  /// The lines are those of a graded bind (validateLines(…, graded)): lines may meet each other and
  /// the cage, and come close to them (set with a graded bind even when `sizing` is null, a cage
  /// and lines without a narrow place).
  bool gradedLines = false;
};

struct SamplingReport {
  Index controls = 0, edge = 0, line = 0, interior = 0, exterior = 0, frame = 0;
  int iterations = 0;        ///< Relaxation iterations (blue noise).
  double seconds = 0.0;
  bool converged = true;     ///< Blue noise: largest move fell below the tolerance.
  double lastMove = 0.0;     ///< Blue noise: largest move of the last iteration / h.
  Index rejectedMoves = 0;   ///< Blue noise: moves refused because they left the region.
};

/// Automatic margin (3h) when options.margin < 0, else options.margin.
double resolvedMargin(const SamplingOptions& options);
/// The frame: [0, width] × [0, height] grown by the margin on every side (the cage must lie in it).
Rect samplingDomain(const SamplingOptions& options);
/// Automatic band width (kExteriorBandSpacings·h) when options.band < 0, else options.band.
double resolvedBand(const SamplingOptions& options);
/// The rectangle the free samples cover: the frame (ExteriorExtent::Frame), or the cage's
/// bounding box grown by resolvedBand on every side and clipped to the frame (Band).
Rect sampledRegion(const Cage& cage, const SamplingOptions& options);

/// About how many samples `sample` would produce (the estimate it checks against kMaxSamples),
/// computed from the sampled region (sampledRegion), h and the cage's perimeter without sampling anything.
double estimateSampleCount(const Cage& cage, const SamplingOptions& options);

/// Samples: control points first (0..m−1, thesis 3.18), then every cage edge at a common
/// spacing ≈ h (kind Edge, with its edge's ends), then free samples covering sampledRegion (the
/// frame, or a band around the cage), each labelled Interior or Exterior. A band's free samples
/// start where the frame's would (the grid is anchored at the origin; blue noise draws its
/// jittered start over the frame's cells and keeps those in the band), so the inside of a band
/// sampling differs from the frame's only through the relaxation.
/// Grid: a regular grid of spacing h, points closer than h/2 to the cage dropped.
/// BlueNoise: fixed frame points on the domain boundary (kind Exterior, stored right after the
/// edge samples: report.frame of them), then interior and exterior samples (jittered start at
/// least h/2 from the cage) relaxed by inverse mean shift (thesis 6.4, Figs 6.6, 6.9), never
/// closer than relax.clearance·h (0.35 h) to the cage. Same seed → same samples on any thread
/// count. For an open cage (sticks) every free sample is Exterior.
/// Throws std::invalid_argument for spacing ≤ 0 or larger than the cage, non-finite input, an
/// invalid cage, a cage outside the domain, or a count above kMaxSamples.
SampleSet sample(const Cage& cage, const SamplingOptions& options, SamplingReport* report = nullptr);

}  // namespace kc::sampling
