#pragma once
/// Gaussian kernel k(x, y) = s · exp(−|x − y|² / 2σ²) (thesis 3.5–3.6), truncated at θ = 5σ (6.1).

#include <cmath>

namespace kc {

struct GaussianKernel {
  double sigma = 1.0;         ///< σ > 0.
  double cutoffFactor = 5.0;  ///< θ = cutoffFactor · σ (thesis 6.1).
  /// Normalization s so that rows of K sum to ≈ 1 in the interior of a sampling (3.1, 3.30).
  double scale = 1.0;

  double cutoff() const { return cutoffFactor * sigma; }
  /// k at squared distance r2 (0 beyond the cut-off).
  double operator()(double r2) const {
    const double c = cutoff();
    return r2 > c * c ? 0.0 : scale * std::exp(-r2 / (2.0 * sigma * sigma));
  }

  /// The kernel for sigma with scale chosen for samples of mean spacing T (density 1/T²):
  /// s = T² / (2πσ²), so that Σ_j k(x, x_j) ≈ 1 (the continuous limit of 3.30).
  static GaussianKernel forSpacing(double sigma, double T);
};

}  // namespace kc
