#pragma once
/// Quality of a point set: separation, fill distance, nearest-neighbour statistics and the
/// radial power spectrum (the blue-noise "gap", thesis Fig 6.10).

#include <Eigen/Core>

#include "kc/core/sizing.h"
#include "kc/core/types.h"
#include "kc/sampling/boundary.h"

namespace kc::sampling {

/// Distance from each row of X to its nearest other row (#X; +∞ for a lone point). O(n) via a
/// uniform grid.
Eigen::VectorXd nearestNeighbourDistances(const Points& X);

/// Mean nearest-neighbour distance T of X (the sampling period of thesis 3.28).
double meanNearestNeighbourSpacing(const Points& X);

/// Smallest distance between a row i ≥ first and any other row of X.
double minimumDistance(const Points& X, Index first = 0);

/// Largest empty circle centred in `domain`: max over domain of the distance to the nearest row
/// of X, evaluated on a probe grid of spacing `probe` (underestimates by at most probe/√2).
double fillDistance(const Points& X, const Rect& domain, double probe);

struct PointSetMetrics {
  double separation = 0.0;    ///< minimumDistance(X, first) / h
  double fill = 0.0;          ///< fillDistance / h
  double nnMean = 0.0;        ///< mean nearest-neighbour distance of rows ≥ first / h
  double nnCv = 0.0;          ///< their coefficient of variation (std / mean)
};

/// All of the above in units of h, for rows ≥ first (e.g. the free samples). probe < 0 → h/8.
PointSetMetrics pointSetMetrics(const Points& X, double h, const Rect& domain, Index first = 0, double probe = -1.0);

/// The same for a graded sampling, in units of the local spacing h(x) = sizing(x): separation =
/// min over rows i ≥ first of (distance to the nearest other row) / h(x_i); nnMean, nnCv of those
/// ratios; fill = max over `domain` of (distance to the nearest row) / h(p), on probes at most
/// h(p)/8 apart (capped at 2: a probe with no row within 2 h(p) reports 2).
PointSetMetrics gradedPointSetMetrics(const Points& X, const SizingField& sizing, const Rect& domain, Index first = 0);

struct RadialSpectrumOptions {
  double omegaMax = -1.0;     ///< Largest angular frequency; < 0 → 3 · 2π / T (T = mean NN spacing).
  int bins = 96;              ///< Radial samples in (0, omegaMax].
  int directions = 24;        ///< Directions averaged per radius (half circle, power is even).
};

/// Radial power spectrum P(ω) = |Σ_j w_j e^{−iω·x_j}|² / Σ_j w_j², averaged over directions, with
/// a Hann window w over the bounding box to suppress leakage from the window edges. Blue noise
/// has P ≈ 0 below a gap frequency and P → 1 at high frequency.
struct RadialSpectrum {
  Eigen::VectorXd omega;      ///< bins, angular frequency
  Eigen::VectorXd power;      ///< bins
};
RadialSpectrum radialPowerSpectrum(const Points& X, const RadialSpectrumOptions& options = {});

}  // namespace kc::sampling
