#pragma once
/// Blue-noise sampling by inverse mean shift (thesis 6.2.1, eq. 6.4, Figs 6.3, 6.6, 6.9).

#include <cstdint>

#include "kc/core/cage.h"
#include "kc/core/types.h"
#include "kc/sampling/boundary.h"
#include "kc/sampling/inverse_mean_shift.h"

namespace kc::sampling {

/// Area per sample of a hexagonal packing at spacing h, in units of h²: √3/2.
inline constexpr double kHexCellFactor = 0.8660254037844386;

struct BlueNoiseOptions {
  /// Area per free sample in units of h² (sets the free-sample count from the region's area).
  double cellArea = 1.0;
  InverseMeanShiftOptions relax;   ///< `spacing` is overwritten with h.
  /// When not empty (a band around the cage, ExteriorExtent::Band): the rectangle whose cells
  /// the jittered start is drawn over (the frame), of which only the points in the sampled domain
  /// are kept — the same start points there as a sampling of the whole cellGrid with this seed.
  Rect cellGrid;
};

/// Upper estimate of the number of samples blue noise puts in `domain` (for limit checks).
double blueNoiseCountEstimate(const Rect& domain, double h, double cellArea);

/// Random start for the free samples: one uniformly jittered point per square cell of area
/// cellArea · h² over `domain` (so the count follows h and the region's area), dropping those
/// closer than h/2 to the cage or to the domain's boundary. Rows are interior points first, then
/// exterior ones; `interiorCount` receives their split. Deterministic in `seed`.
/// `obstacles` (obstacleEdges: the cage and the structure lines), when given, is what the h/2
/// distance is measured to instead of the cage. `cellGrid`, when given and not empty, is where
/// the cells are laid and the random stream drawn (see BlueNoiseOptions::cellGrid); it should
/// contain `domain`.
Points jitteredStart(const Cage& cage, const Rect& domain, double h, double cellArea, std::uint64_t seed,
                     Index& interiorCount, const Cage* obstacles = nullptr, const Rect* cellGrid = nullptr);

/// Expected number of free samples of the graded start over `domain` (gradedStart before the
/// samples near the cage are dropped): Σ over its cells of side² / (cellArea·h(centre)²).
double gradedCountEstimate(const Rect& domain, const SizingField& sizing, double cellArea);

/// Random start for the free samples of a graded sampling: cells of side √cellArea·hMax over
/// `domain` (or over `cellGrid`, keeping those meeting `domain`), split into four while larger than
/// 2·√cellArea·h(centre), each leaf worth side²/(cellArea·h(centre)²) samples (up to 4). A leaf the
/// obstacles or the domain's boundary come near splits its worth between the inside and the
/// outside of the cage by the fractions of a stratified 4×4 set of probes on each (probes closer
/// than h/2 to them count for neither); each side holds one uniformly placed sample each time its
/// running sum of worth (in the quadtree's order, from a random offset) passes a whole number, so
/// the density is 1/(cellArea·h(x)²) without clumps or empty runs, and a corridor between two
/// parts of the cage gets the count its area needs; samples closer than h(p)/2 to the obstacles or
/// the domain's boundary are dropped. Positions are drawn per cell (seed and cell). Rows: interior
/// first.
Points gradedStart(const Cage& cage, const Rect& domain, const SizingField& sizing, double cellArea, std::uint64_t seed,
                   Index& interiorCount, const Cage* obstacles = nullptr, const Rect* cellGrid = nullptr);

struct BlueNoiseResult {
  SampleSet samples;               ///< controls, edges, frame (Exterior), interior, exterior
  Index frameCount = 0;            ///< fixed frame points, stored right after the edge samples
  Index interiorCount = 0, exteriorCount = 0;  ///< free samples
  InverseMeanShiftReport relax;
};

/// Graded (options.relax.sizing set and graded()): every spacing below is the local h(x) of the
/// sizing field (boundarySamples, framePoints and line samples at the local spacing, gradedStart,
/// the relaxation at the local bandwidth); h is then the sizing's hMax.
/// Fixed samples (controls, edges at spacing h, a frame of points on `domain`'s boundary at
/// spacing h, dropped within h/2 of the cage), then free samples from jitteredStart relaxed by
/// inverse mean shift with the fixed ones held in place. Free samples keep their region: interior
/// samples stay inside the cage, exterior ones outside it and inside the domain.
/// No input checks: `sample` validates.
/// Structure `lines` (validated by the caller) get fixed samples too (appendLineSamples, stored
/// right after the edge samples, before the frame) and free samples keep their distance from
/// them as from the cage (thesis 5.3.3: samples on edges and lines are kept fixed).
BlueNoiseResult blueNoiseSample(const Cage& cage, const Rect& domain, double h, std::uint64_t seed,
                                const BlueNoiseOptions& options = {}, std::span<const StructureLine> lines = {});

/// `count` blue-noise points in `rect` (no cage): jittered start, then inverse mean shift on the
/// torus (periodic boundary, like Balzer et al.'s point sets used in thesis 3.3.2), spacing
/// h = sqrt(area / (count · kHexCellFactor)). count×2, every point inside rect.
Points blueNoiseRectangle(Index count, const Rect& rect, std::uint64_t seed, InverseMeanShiftOptions relax = {},
                          InverseMeanShiftReport* report = nullptr);

}  // namespace kc::sampling
