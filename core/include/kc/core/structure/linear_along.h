#pragma once
/// Making a kernel field linear along segments (thesis 5.3.3, last step): the weights of the
/// samples near a line are post-processed so that the field — evaluated anywhere on the line, not
/// only at its samples — varies linearly between the line's two base points.

#include <span>
#include <vector>

#include "kc/core/field/kernel_field.h"
#include "kc/core/types.h"

namespace kc {

/// A segment a → b along which the weights must be wa (1×m) at a, wb at b and linear between.
struct LinearSegment {
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
  Eigen::RowVectorXd wa, wb;
};

struct LinearityOptions {
  double fitSpacing = 0.25;  ///< Fit points along a segment about every fitSpacing·σ(p), σ(p) the kernel's width there.
  double reach = 2.5;        ///< Samples within reach·σ of a segment are adjusted (σ: the largest width along it).
  double rankTolerance = 1e-6;   ///< Relative pivot threshold of the least-norm fit (larger: smaller changes, looser fit).
  int sweeps = 1;                ///< Passes over all segments (a second pass settles what later segments
                                 ///< moved at the fit points of earlier ones, as at the corners of a cage).
  double holdWeight = 1.0;       ///< Weight of the side conditions (held samples, other lines, PᵀΔU = 0) against the fit
                                 ///< (larger weights make the COD drop fit directions: 10 gave a 40× looser fit on the star).
  double freeWeight = 0.003;     ///< Weight of k(x_i, X_N) ΔU ≈ 0 at the samples that are not held but within the change's
                                 ///< reach: keeps their weights near the optimized ones (0: only the least-norm ΔU limits them).
};

struct LinearityReport {
  double before = 0.0;   ///< max |w(p) − linear(p)| over the fit points, before.
  double after = 0.0;    ///< The same after (evaluated through the re-solved field).
  Index adjusted = 0;    ///< Samples whose kernel coefficients changed.
  Index changedRows = 0; ///< Rows of W that changed.
  Index fitPoints = 0;   ///< Fit points over all segments (the rows of the fit, a measure of its cost).
  double seconds = 0.0;
};

/// Post-processes W (#S×m, the field's data weights) so that `field` is linear along every
/// segment, then re-solves the field (field.update(W)). Segment by segment, the kernel
/// coefficients ΔU of the samples N within reach·σ of the segment solve, in the least-norm
/// sense (complete orthogonal decomposition),
///   k(F_s, X_N) ΔU = −(w(F_s) − linear(F_s))   at the fit points F_s of the segment, spaced by
///                         fitSpacing·σ(p) (dense only where a graded width is small) and weighted
///                         by √(σ(p)/σ_min) (the quadrature of the misfit along the segment),
///   k(x_i, X_N) ΔU = 0   at every sample i with keep[i] within the reach of ΔU (controls, edge and
///                         line samples: Lagrange and the other lines' weights stay as they are),
///   k(F_t, X_N) ΔU = 0   at the fit points of every other segment t within that reach,
///   [1 x y]_Nᵀ ΔU = 0    (exact mode: the polynomial side condition PᵀU = 0 of 1.9 / 6.2),
///   k(x_i, X_N) ΔU ≈ 0   softly (weight freeWeight) at the other samples within the change's reach,
/// and W += K(·, N) ΔU. The field's coefficients become U + ΔU with B unchanged: every change is
/// a sum of kernels within reach·σ + θ of the segment (weights farther away are untouched), and
/// since each row of ΔU is a combination of rows w(F) − linear(F), which satisfy 1ᵀe = 0 and
/// Cᵀe = 0, partition of unity and reproduction stay exact. `keep` has #S entries (non-zero:
/// held). The fit and the side conditions are met to about rankTolerance (relative); the held
/// rows are then put back to their exact values
/// (W(keep) as given) and the field re-solved, so Lagrange and the held samples' weights are
/// exact to round-off while the fit loosens by about as much.
LinearityReport makeLinearAlong(KernelField& field, std::span<const LinearSegment> segments, const std::vector<char>& keep,
                                Weights& W, const LinearityOptions& options = {});

}  // namespace kc
