#pragma once
/// Per-sample ℓ1 optimization (thesis 4.8) solved exactly as a small linear program.

#include <span>

#include "kc/core/weights/sample_qp.h"

namespace kc {

struct L1Options {
  int maxIterations = 200;   ///< Simplex pivots.
  double tolerance = 1e-12;  ///< Dual feasibility |a_iᵀy| ≤ 1 + tol; residual bound |A w − b|∞.
};

/// Per-sample ℓ1 (thesis 4.8): min |v|₁ s.t. A v = b − A w0, w = w0 + v — the exact LP optimum.
///
/// Primal simplex on the standard form v = p − q, p, q ≥ 0, min 1ᵀ(p + q): three rows and 2m
/// columns ±a_i. Because both signs of every column exist, any three affinely independent
/// control points give a feasible starting basis (the sign of each basic column is chosen so
/// the basic values are ≥ 0) — no phase 1. The start is the triangle most aligned with the QEC
/// correction (its ℓ2 analogue); pricing is Dantzig's rule (largest |a_iᵀy| − 1), switching to
/// Bland's rule after a run of degenerate pivots, which excludes cycling. The basis inverse is
/// recomputed from scratch each pivot (3×3). Certified by primal feasibility (basic values ≥ 0),
/// dual feasibility (|a_iᵀy| ≤ 1 + tol, y = B⁻ᵀ1) and the residual |A w − b|∞.
/// The LP is always feasible (A has full row rank); on a non-certified end the QEC solution is
/// returned with status Failed.
///
/// w0, w: length m; w must not alias w0. xh: normalized position (ControlFrame::normalize).
SampleReport sampleL1(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, std::span<double> w,
                      const L1Options& options = {});

}  // namespace kc
