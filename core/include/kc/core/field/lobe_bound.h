#pragma once
/// A lower bound on a coordinate field's weights, applied where the field is evaluated.
///
/// The QP (4.1) keeps the data weights W ≥ 0 at the samples, but the kernel interpolant between
/// them undershoots where the data kink (a weight falling to 0, the edges' hat functions at the
/// cage's vertices): lobes of −0.03 to −0.05 within a spacing of the kink, which a drag moves
/// against its direction. The bound replaces the interpolant's weights w(x) at a point where one of
/// them is below ℓ(x) by their projection, the QP (4.1) at x with w(x) as its target and the bound
/// ℓ(x) in place of 0:
///
///   w̃(x) = argmin Σ_j (v_j − w_j(x))²/a_j   s.t.   Cᵀv = x,  1ᵀv = 1,  v ≥ ℓ(x),
///
///   ℓ(x) = −depth inside the cage and on it,   −depth − d(x)/fade outside (d: distance to the cage),
///
/// a_j = allowanceOf(w_j(x), ε) (optimizer.h; ε = 0: a_j = 1, Euclidean): as in the QP's
/// allowance metric, the weight that lifts a lobe is given back by the controls that are large at x,
/// not spread over the far ones. So partition of unity and reproduction stay exact, the weights inside never fall below
/// −depth, and w̃ is continuous everywhere (the projection onto a polytope is 1-Lipschitz, and ℓ is
/// continuous): outside the cage the bound relaxes within a few pixels, where the field's weights
/// may be negative by design (the exterior's odd reflection, exterior_continuation.h). Points whose
/// weights are all ≥ ℓ(x) keep w(x) bit for bit; the controls and the edges' hat functions are ≥ 0
/// and stay exact. w̃ is piecewise smooth: it has a kink where a weight meets the bound.
///
/// The gradient of w̃ on its active set J = {j : w̃_j = ℓ} (free set F), where w̃_F = w_F + D_F A_Fᵀλ
/// (D = diag(a)):
///   ∂w̃_J = ∂ℓ,   ∂w̃_F = ∂w_F + ∂D_F A_Fᵀλ + D_F A_Fᵀ ∂λ,
///   ∂λ = (A_F D_F A_Fᵀ)⁻¹ (∂b − A_J 1 ∂ℓ − A_F ∂w_F − A_F ∂D_F A_Fᵀλ),
/// with A = [Ĉᵀ; 1ᵀ] and b = [x̂; 1] in the normalized frame (ControlFrame), ∂a_j = ∂w_j where
/// 0 < w_j < kAllowanceCap·ε and 0 elsewhere.

#include <span>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/types.h"
#include "kc/core/weights/sample_qec.h"

namespace kc {

/// Weights inside the cage stay ≥ −kLobeDepth by default: a 40 px drag of a control then moves no
/// pixel inside the cage half a pixel or more against the drag (the 0.0125 level of the drag area,
/// `kcwarp-cli stats`).
inline constexpr double kLobeDepth = 0.0125;

class LobeBound {
 public:
  /// cage: a cage with an interior (hasInterior), whose points are the field's controls (column j of
  /// the weights is control j); depth ≥ 0 (the bound inside is −depth); fade > 0 pixels; allowance
  /// ε ≥ 0 of the metric (0: Euclidean). Throws std::invalid_argument otherwise (and for a
  /// degenerate cage, as ControlFrame).
  LobeBound(const Cage& cage, double depth, double fade, double allowance = 0.0);
  LobeBound(const LobeBound&) = delete;  // m_queries refers to m_cage
  LobeBound& operator=(const LobeBound&) = delete;

  double depth() const { return m_depth; }
  double fade() const { return m_fade; }
  double allowance() const { return m_allowance; }
  /// ℓ(x) (see the header).
  double bound(const Vec2& x) const;

  /// ℓ at every row of P.
  std::vector<double> bounds(const Points& P) const;

  /// Projects the rows of W (#P×m, the field's weights at the rows of P) that have a weight below
  /// their bound; the others are left as they are. Returns the rows it changed, increasing.
  /// Parallel over rows; each row's result is independent of the thread count.
  std::vector<Index> apply(const Points& P, Weights& W) const;
  /// The same for the rows `rows` of W only (all rows when empty).
  std::vector<Index> apply(const Points& P, Weights& W, const std::vector<Index>& rows) const;
  /// The same for the rows `rows` with their bounds given (`bounds`: ℓ at the rows of P, as
  /// bounds(P); only the entries of `rows` are read): for a fixed point set evaluated many times
  /// (app::FieldSampler).
  void project(const Points& P, std::span<const double> bounds, const std::vector<Index>& rows, Weights& W) const;
  /// Turns the gradients dWdx, dWdy of the unbounded field at P (whose weights there are `W`,
  /// unbounded) into those of the bounded field, in the rows where the bound is active.
  void applyGradients(const Points& P, const Weights& W, Weights& dWdx, Weights& dWdy) const;

 private:
  /// Projects w (the weights at x) onto w ≥ l when a weight is below l; false when none is.
  bool projectRow(const Vec2& x, double l, std::span<double> w, std::vector<double>& target, std::vector<double>& a) const;
  void checkShapes(const Points& P, const Weights& W) const;

  Cage m_cage;
  CageQueries m_queries;
  ControlFrame m_frame;
  double m_depth = 0.0, m_fade = 1.0, m_allowance = 0.0;
};

}  // namespace kc
