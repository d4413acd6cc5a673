#pragma once
/// Weights outside the cage for the pinned outside mode: the image border stays where it is and
/// the background between the cage and the border stretches smoothly.
///
/// Each control's exterior weight h_i is the harmonic extension of the cage's piecewise-linear
/// edge data into the exterior Ω (the image minus the cage's interior):
///     Δh_i = 0 in Ω,   h_i = λ_i on the cage,   h_i = 0 on the image border,
/// where λ_i is the Lagrange / edge-linear data (1 at control i, linear along its edges, 0 on the
/// other edges). A fixed anchor with the identity transform takes the rest, a = 1 − Σ_i h_i, so the
/// deformation outside is f(x) = Σ_i h_i(x) T_i x + a(x) x (thesis 3.37 with one extra, never
/// moved handle). On the cage a = 0 and f follows the cage's edges; on the border a = 1 and f = x.
/// By the maximum principle h_i ∈ [0, 1] and Σ_i h_i ∈ [0, 1].
///
/// Discretization: the 5-point Laplacian (the P1 cotangent Laplacian of the warp mesh's
/// right-triangle grid) on the grid vertices outside the cage. A grid edge that meets the cage at
/// a fraction θ of its length from an exterior vertex is cut there and couples that vertex to the
/// edge data at the crossing with weight c/θ (Gibou, Fedkiw, Cheng, Kang 2002, "A second-order-
/// accurate symmetric discretization of the Poisson equation on irregular domains"). The matrix is
/// a symmetric M-matrix, so the discrete maximum principle holds and h_i ∈ [0, 1] on the grid too;
/// thin parts of the cage (narrower than a grid cell) still separate the two sides. One sparse
/// Cholesky factorization, m right-hand sides.
///
/// Open sticks (edges on no loop: a stick figure's limbs, a tree's branches) stand for a part of
/// the picture around them. With a stick band (ExteriorWeightsOptions::stickBand) the grid
/// vertices near a stick take the coordinate field's weights, as the inside of a loop does, and the
/// harmonic extension starts at the band's edge: there its data are the field's weights at the
/// band's vertices (setFieldData), so the map is continuous across the band's edge and the paint
/// around a stick moves with it, while the background beyond stretches to the pinned border.

#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc {

/// Sparse row-major weights, one row per point; the storage of the warp mesh's compact weights.
using CompactWeights = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

struct ExteriorWeightsOptions {
  /// Entries with |h_i| ≤ keepThreshold / m are dropped; the anchor absorbs them (rows still sum to 1).
  double keepThreshold = 1e-3;
  /// Smallest cut fraction θ used in the stencil (a vertex on the cage gets weight c/θ ≥ 1000c).
  double minCutFraction = 1e-3;
  /// Image-border vertices closer than this (pixels) to the cage follow the cage (they take its edge
  /// data at the closest point, anchor 0) instead of staying pinned: where a cage is drawn along
  /// the picture's edge there is no background to stretch, and that edge moves with the cage.
  double followDistance = 4.0;
  /// The band around open sticks, as a fraction of each stick's length: grid vertices closer to a
  /// stick than max(stickBand · its length, stickBandCells grid-cell diagonals) and outside every
  /// loop take the coordinate field's weights (see the file comment). 0: no band (the extension
  /// starts on the sticks themselves).
  double stickBand = 0.0;
  /// The band's smallest radius in grid-cell diagonals (> 1, so that no grid edge from a solved
  /// vertex crosses a stick).
  double stickBandCells = 1.5;
};

struct ExteriorWeightsReport {
  Index unknowns = 0;       ///< Exterior grid vertices solved for (not on the image border).
  Index anchored = 0;       ///< Exterior vertices on the image border (h = 0, anchor 1).
  Index following = 0;      ///< Border vertices within followDistance of the cage (edge data, no anchor).
  Index interior = 0;       ///< Vertices inside the cage or in a stick band (weights from the coordinate field).
  Index band = 0;           ///< Of those, vertices in a stick band.
  Index cutEdges = 0;       ///< Grid edges from an unknown vertex that meet the cage.
  Index fallbackEdges = 0;  ///< Edges to an interior vertex with no crossing found (rounding): data at its closest cage point.
  double minWeight = 0.0;   ///< min_i,v h_i(v) of the solution before dropping (≥ 0 up to rounding).
  double maxWeight = 0.0;   ///< max_i,v h_i(v) (≤ 1 up to rounding).
  double maxSum = 0.0;      ///< max_v Σ_i h_i(v) (≤ 1 up to rounding).
  bool ok = true;           ///< False when the factorization failed (then H holds the anchor only).
  double assembleSeconds = 0.0, factorSeconds = 0.0, solveSeconds = 0.0;
};

/// The factorization and the right-hand side's parts of a solve whose data include the field's
/// weights in a stick band (private to exterior_weights.cpp).
struct ExteriorSystem;

/// Exterior weights on a rectilinear grid: vertex v = j·nx + i sits at (xs[i], ys[j]).
struct ExteriorWeights {
  /// Per vertex: 1 outside the cage (row of H used), 0 inside or in a stick band (the coordinate
  /// field's weights).
  std::vector<std::uint8_t> exterior;
  /// Per vertex: 1 in a stick band (then also exterior 0); empty without a band.
  std::vector<std::uint8_t> band;
  /// #V×(m+1): for exterior vertices h_0..h_{m−1} and, in column m, the anchor 1 − Σ_i h_i (kept
  /// entries only, so every exterior row sums to 1); rows of interior vertices are empty. With a
  /// stick band, the exterior rows hold the anchor only until setFieldData() gives the band's data.
  CompactWeights H;
  ExteriorWeightsReport report;
  /// Non-null when band vertices are data of the solve (kept for setFieldData; shared by copies,
  /// immutable, solves serialized).
  std::shared_ptr<const ExteriorSystem> system;
  /// True when H depends on the field's weights (a stick band touches the solved vertices).
  bool needsFieldData() const { return system != nullptr; }
};

/// The pinned-mode exterior weights (see the file comment) on the grid xs × ys (increasing,
/// uniform steps; the first and last lines are the image border) for `cage` (validated by the
/// caller): closed cages (several loops allowed, even-odd interior) and open sticks (no
/// interior: the extension is taken from both sides of each stick). Vertices inside the cage are
/// classified by the even-odd rule along grid rows, consistently with the cut edges.
ExteriorWeights pinnedExteriorWeights(const std::vector<double>& xs, const std::vector<double>& ys, const Cage& cage,
                                      const ExteriorWeightsOptions& options = {});

/// With a stick band (ext.needsFieldData()): solves the exterior again with the field's weights
/// W (#rows ≥ the grid's vertex count, m columns, rows of band vertices used) as the data on the
/// band's edge, and replaces ext.H and the report's weight range: h = A⁻¹(B_cage + B_band W⁺_band),
/// the same factorization, m right-hand sides, where W⁺ is W with its negative entries set to 0
/// and each row rescaled to sum 1 (the field's small negative lobes: the map's step at the band's
/// edge is that mass times the displacement). So h_i ∈ [0, 1] and Σ_i h_i + anchor = 1 still
/// hold (maximum principle). Does nothing without a band. Throws std::invalid_argument on a shape
/// mismatch.
void setFieldData(ExteriorWeights& ext, const Weights& W);

}  // namespace kc
