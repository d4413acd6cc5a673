#pragma once
/// Gaussian kernel k(x, y) = s · exp(−|x − y|² / 2σ²) (thesis 3.5–3.6), truncated at θ = 5σ (6.1),
/// and its variable-width form for graded samplings.
///
/// Variable width (`width` set and graded): σ(x) = sigma · h(x) / h.hMax() follows the sampling's
/// local spacing h, and the kernel is Gibbs's non-stationary Gaussian
///
///   k(x, y) = s · (2 σ_x σ_y / (σ_x² + σ_y²)) · exp(−|x − y|² / (σ_x² + σ_y²)),
///
/// positive definite for every positive width function σ (M. N. Gibbs, "Bayesian Gaussian
/// processes for regression and classification", PhD thesis, Cambridge 1997; C. Paciorek and
/// M. Schervish, "Nonstationary covariance functions for Gaussian process regression", NIPS 2003,
/// Theorem 1 with Σ(x) = 2σ(x)² I in two dimensions). Why: with g_x(u) = exp(−|u − x|²/σ_x²)/σ_x,
/// ∫ g_x(u) g_y(u) du = (π/2) · (2σ_xσ_y/(σ_x² + σ_y²)) · exp(−|x − y|²/(σ_x² + σ_y²)), the kernel
/// up to the constant π/(2s), so K is a Gram matrix of functions in L²:
/// Σ a_i a_j k(x_i, x_j) = (2s/π) ‖Σ a_i g_{x_i}‖² > 0 for a ≠ 0 at distinct points (the Gaussians
/// g_{x_i} are linearly independent). With σ_x = σ_y = σ it is the Gaussian above
/// exactly. It is truncated where it falls below e^{−θ²/2σ²} times s (θ = cutoffFactor · σ),
/// like the constant kernel: at |x − y|² > (σ_x² + σ_y²)(θ²/2σ² + ln(2σ_xσ_y/(σ_x² + σ_y²))).

#include <cmath>
#include <memory>

#include <Eigen/Core>

#include "kc/core/sizing.h"
#include "kc/core/types.h"

namespace kc {

struct GaussianKernel {
  double sigma = 1.0;         ///< σ > 0 (the constant width; with `width`, σ where h = hMax).
  double cutoffFactor = 5.0;  ///< θ = cutoffFactor · σ (thesis 6.1).
  /// Normalization s so that rows of K sum to ≈ 1 in the interior of a sampling (3.1, 3.30).
  double scale = 1.0;
  /// The local spacing the width follows (graded samplings); null or not graded: constant σ.
  std::shared_ptr<const SizingField> width;

  /// True when σ varies (width set and graded).
  bool variable() const { return width && width->graded(); }
  /// The largest cut-off distance, θ = cutoffFactor · σ (σ is the largest width).
  double cutoff() const { return cutoffFactor * sigma; }
  /// k at squared distance r2 for the constant width (0 beyond the cut-off).
  double operator()(double r2) const {
    const double c = cutoff();
    return r2 > c * c ? 0.0 : scale * std::exp(-r2 / (2.0 * sigma * sigma));
  }

  /// σ(x) (sigma when the width is constant).
  double widthAt(const Vec2& x) const { return variable() ? sigma * width->profile(x) / width->hMax() : sigma; }
  /// σ(x) and ∇σ(x) (zero when the width is constant).
  double widthAt(const Vec2& x, Vec2& gradient) const;
  /// σ at every row of X (#X).
  Eigen::VectorXd widthsAt(const Points& X) const;
  /// Search radius around a point of width sx that holds every y with k(x, y) ≠ 0.
  double reach(double sx) const { return variable() ? cutoffFactor * std::sqrt(0.5 * (sx * sx + sigma * sigma)) : cutoff(); }
  /// k(x, y) at squared distance r2 for widths sx = σ(x), sy = σ(y) (Gibbs); operator()(r2) when
  /// the width is constant.
  double operator()(double r2, double sx, double sy) const {
    if (!variable()) return (*this)(r2);
    const double S = sx * sx + sy * sy, A = 2.0 * (sx * sy) / S;  // symmetric in sx, sy to the bit
    const double c = 0.5 * cutoffFactor * cutoffFactor;
    if (r2 > S * c) return 0.0;  // beyond the cut-off for any A ≤ 1, without a log or an exp
    return r2 > S * (c + std::log(A)) ? 0.0 : scale * A * std::exp(-r2 / S);
  }
  /// ∇_x k(x, y) / k(x, y) for x − y = d, widths sx, sy and ∇σ(x) = gx:
  /// −2d/S + gx (2 sx |d|²/S² + 1/sx − 2 sx/S), S = sx² + sy²; −d/σ² for the constant width (3.42).
  Vec2 gradientFactor(const Vec2& d, double sx, const Vec2& gx, double sy) const {
    if (!variable()) return -d / (sigma * sigma);
    const double S = sx * sx + sy * sy;
    return -2.0 / S * d + (2.0 * sx * d.squaredNorm() / (S * S) + 1.0 / sx - 2.0 * sx / S) * gx;
  }

  /// The kernel for sigma with scale chosen for samples of mean spacing T (density 1/T²):
  /// s = T² / (2πσ²), so that Σ_j k(x, x_j) ≈ 1 (the continuous limit of 3.30). With a variable
  /// width, T/σ is the same everywhere (σ ∝ h ∝ T), so the one scale serves the whole sampling.
  static GaussianKernel forSpacing(double sigma, double T);
};

}  // namespace kc
