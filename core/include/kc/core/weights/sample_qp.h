#pragma once
/// Per-sample quadratic program (thesis 4.1) solved exactly in its 3-variable dual.

#include <span>

#include "kc/core/weights/sample_qec.h"
#include "kc/core/solve.h"

namespace kc {

struct QpOptions {
  int maxIterations = 100;      ///< Newton iterations (each one O(m)).
  double tolerance = 1e-13;     ///< Max-norm of the equality residual A w − b (normalized units).
  double hullTolerance = 1e-12; ///< x̂ farther than this outside the hull is treated as infeasible.
};

struct SampleReport {
  SolveStatus status = SolveStatus::Ok;  ///< Ok (KKT certified), Infeasible (QP only), NotConverged.
  int iterations = 0;
  double residual = 0.0;  ///< |A w − b|∞ of the returned w (normalized units).
};

/// Per-sample QP (thesis 4.1): min |w − w0|² s.t. Ĉw = x̂, 1ᵀw = 1, w ≥ 0 — the exact optimum.
///
/// The problem is the Euclidean projection of w0 onto a polytope cut by only three equalities,
/// so it is solved in its dual over λ ∈ R³: w(λ) = max(0, w0 + Aᵀλ) and the convex, C¹,
/// piecewise-quadratic f(λ) = ½|w(λ)|² − bᵀλ. Semismooth Newton (generalized Hessian
/// A_S A_Sᵀ over the positive set S, tiny Levenberg term when S is rank deficient, Armijo line
/// search with safeguarded quadratic backtracking) starts from the QEC multipliers (4.4), so a
/// QEC solution that is already non-negative costs one pass. On each piece f is quadratic, so a
/// full Newton step is the exact equality-constrained solve on S; the result is certified by the
/// KKT conditions: w ≥ 0 and complementarity hold by construction of w(λ), stationarity and
/// primal feasibility by |A w − b|∞ ≤ tolerance.
///
/// Infeasible x̂ (outside the convex hull of the control points): there is no w ≥ 0. Fallback:
/// min |w − w0|² s.t. Aw = b, w ≥ −t with the smallest t ≥ 0 that makes it feasible. With
/// u = w + t1 ≥ 0 this is the QP above for the point βx̂ on the segment from x̂ to the centroid
/// where it meets the hull (β = hullShrink, t = (1 − β)/(mβ)), so it is solved by the same code.
/// Partition of unity and reproduction stay exact, the most negative weight is as small as any
/// affine-reproducing weights allow, and the weights are continuous across the hull boundary
/// (t → 0 there), unlike switching to QEC, which would jump. Reported as Infeasible. βx̂ is taken
/// 64 units of rounding inside the hull: exactly on it the feasible set is one edge's controls or
/// one vertex, and rounding can put the point just outside, where Newton cannot converge.
/// On and near the hull boundary the optimal λ is large (it runs along the boundary's normal) and
/// the positive set often lies on one line (H singular): the last step is then evaluated
/// incrementally on the positive set, which avoids the cancellation in w0 + Aᵀλ, and on a
/// singular H the step along its null space goes to the first control that becomes positive.
/// Newton ending its iterations with the residual within 10× the tolerance (a positive set that
/// cycles among rounding-level weights) counts as certified. If Newton is not certified within
/// maxIterations otherwise (not seen in the tests, which include samples
/// on hull edges and vertices for m up to 3,000), w = the last iterate projected onto Aw = b
/// (exact constraints, moved only by the residual) and status NotConverged; report.residual is the
/// iterate's residual before that projection.
///
/// w0, w: length m; w must not alias w0. xh: normalized position (ControlFrame::normalize).
SampleReport sampleQp(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, std::span<double> w,
                      const QpOptions& options = {});

/// The same in the diagonal metric Σ_j (w_j − w0_j)²/a_j (allowance a > 0, length m; empty: the
/// plain QP above): controls with a small a_j carry little of the correction. A sample outside the
/// hull, and one the metric's Newton does not certify, get sampleQp's weights (outside, the
/// fallback's point lies on the hull's boundary, where the feasible weights are one edge's or one
/// vertex's whatever the metric).
SampleReport sampleQpWeighted(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0,
                              std::span<const double> allowance, std::span<double> w, const QpOptions& options = {});

/// The QP with a lower bound other than 0: min Σ (w − w0)²/a_j (a = allowance; empty: Euclidean)
/// s.t. Ĉw = x̂, 1ᵀw = 1, w ≥ bound (bound ≤ 0), through u = w − bound ≥ 0, which is the QP above at
/// βx̂ with the target β(w0 − bound), β = 1/(1 − m·bound). Outside the hull the bound is lowered to
/// the least one that is feasible there (the fallback's). What projects an interpolant's weights
/// at a point onto w ≥ bound (LobeBound). Throws std::invalid_argument for bound > 0.
SampleReport sampleQpAbove(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, double bound,
                           std::span<const double> allowance, std::span<double> w, const QpOptions& options = {});

}  // namespace kc
