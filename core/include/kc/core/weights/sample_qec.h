#pragma once
/// Shared per-sample constraint data (A = [Cᵀ; 1ᵀ], (AAᵀ)⁻¹, convex hull) and the closed-form
/// quadratic cost with equality constraints, QEC (thesis 4.2–4.6).

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "kc/core/types.h"

namespace kc {

/// What every per-sample problem of chapter 4 shares: the constraint matrix A = [Ĉᵀ; 1ᵀ] (3×m)
/// in normalized coordinates Ĉ = (C − c̄)/s (c̄ = centroid, s = RMS radius of the control
/// points), (AAᵀ)⁻¹, and the convex hull of Ĉ as half-planes. Normalization changes no optimum:
/// with 1ᵀw = 1, Cw = x ⇔ Ĉw = x̂ = (x − c̄)/s; it only keeps the 3×3 systems well conditioned
/// for cages given in pixels. Build once per cage, share read-only between threads.
class ControlFrame {
 public:
  ControlFrame() = default;
  /// C: m×2 control points. Throws std::invalid_argument when m < 3, C is not finite or all
  /// points are collinear (A would not have full row rank).
  explicit ControlFrame(const Points& C);

  Index size() const { return m_m; }
  /// Normalized position x̂ = (x − c̄)/s of a point given in the control points' coordinates.
  Vec2 normalize(const Vec2& x) const { return (x - m_center) / m_scale; }
  /// Normalized control coordinates (length m each).
  const double* cx() const { return m_cx.data(); }
  const double* cy() const { return m_cy.data(); }
  /// Products x², xy, y² of the normalized control coordinates (the QP's Hessian sums).
  const double* cxx() const { return m_cxx.data(); }
  const double* cxy() const { return m_cxy.data(); }
  const double* cyy() const { return m_cyy.data(); }
  /// (AAᵀ)⁻¹ with A = [Ĉᵀ; 1ᵀ].
  const Eigen::Matrix3d& aatInv() const { return m_aatInv; }
  /// AAᵀ.
  const Eigen::Matrix3d& aat() const { return m_aat; }
  /// Three hull vertices spanning a large triangle (a well-conditioned basis for the ℓ1 simplex).
  const std::array<int, 3>& baseTriangle() const { return m_baseTriangle; }

  /// Largest signed distance of x̂ outside the hull's edge lines (≤ 0 inside; normalized units).
  double hullExcess(const Vec2& xh) const;
  /// For x̂ outside the hull: the largest β ∈ (0, 1] with βx̂ in the hull (the centroid, the
  /// origin of the normalized frame, lies strictly inside). Returns 1 for x̂ inside.
  double hullShrink(const Vec2& xh) const;

 private:
  Index m_m = 0;
  Vec2 m_center = Vec2::Zero();
  double m_scale = 1.0;
  std::vector<double> m_cx, m_cy, m_cxx, m_cxy, m_cyy;
  Eigen::Matrix3d m_aat = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d m_aatInv = Eigen::Matrix3d::Zero();
  std::array<int, 3> m_baseTriangle = {0, 1, 2};
  std::vector<Vec2> m_hullNormal;  ///< Outward unit normals of the hull edges.
  std::vector<double> m_hullOffset;  ///< n·p for a point p on each edge (> 0).
};

/// QEC (thesis 4.2–4.6): min |w − w0|² s.t. Ĉw = x̂, 1ᵀw = 1, in the equivalent form
/// w = w0 + Aᵀλ, λ = (AAᵀ)⁻¹(b − A w0), b = [x̂; 1]. w0, w: length m (may alias).
/// Returns λ (the multipliers, used to warm-start the QP). O(m), no allocation.
Eigen::Vector3d sampleQec(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0,
                          std::span<double> w);

/// The QEC multipliers λ = (AAᵀ)⁻¹(b − A w0) of the line above alone (no w written): the
/// warm start of the QP's dual Newton iteration. O(m).
Eigen::Vector3d qecMultipliers(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0);

/// Linear precision on an edge (thesis 4.7): w_k, w_l of x on the segment c_k–c_l, all other
/// weights zero. x in the control points' coordinates; w has length m.
void edgeWeights(const Points& C, int k, int l, const Vec2& x, std::span<double> w);

}  // namespace kc
