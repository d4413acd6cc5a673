#pragma once
/// Choosing the kernel scale σ for a point set, and showing whether a σ is good: thesis 3.2
/// (σ̂ = 3T/π, eq. 3.28), Fig 6.10 (spectral choice), Figs 3.1 / 3.3 (row sums of K).

#include "kc/core/sizing.h"
#include "kc/core/types.h"
#include "kc/sampling/point_metrics.h"

namespace kc::sampling {

/// σ̂ = 3T/π (3.28): the Gaussian's Fourier transform is e⁻¹⁸ ≈ 1.5e-8 of its peak at the first
/// alias frequency 2π/T of a sampling of period T.
double sigmaFromSpacing(double T);

/// σ̂ (3.28) with T the mean nearest-neighbour spacing of the samples. What `bind` uses by default.
double suggestSigma(const Points& X);
double suggestSigma(const SampleSet& S);
/// For a graded sampling: σ where h = hMax, from the mean of each sample's nearest-neighbour
/// distance in units of its local spacing (T/h is the same everywhere, so σ(x) = σ · h(x)/hMax);
/// suggestSigma(X) when `sizing` is not graded.
double suggestSigma(const Points& X, const SizingField& sizing);

struct SpectralSigmaOptions {
  RadialSpectrumOptions spectrum;
  /// The gap ends at the first frequency where the power spectrum reaches this level (blue noise
  /// tends to 1 at high frequency; a grid jumps from 0 to its first peak at 2π/T).
  double gapLevel = 0.5;
  /// σ puts the Fourier-domain Gaussian e^{−σ²ω²/2} at this fraction of its peak at the gap's
  /// end: σ = sqrt(−2 ln ratio) / ω_gap. The default e⁻¹⁸ gives σ̂ = 3T/π on a regular grid.
  double ratio = 1.522997974471263e-08;
};

struct SpectralSigma {
  double sigma = 0.0;
  double gapOmega = 0.0;       ///< ω_gap, angular frequency where the gap ends
  RadialSpectrum spectrum;     ///< the spectrum it was read from (plot it against the Gaussian)
};

/// Spectral choice of σ (thesis Fig 6.10): radial power spectrum of X, find where its low-power
/// gap ends (ignoring the window's leakage near ω = 0), and choose σ so the kernel's Fourier
/// transform has decayed to `ratio` there. sigma = 0 when no gap end is found.
SpectralSigma spectralSigma(const Points& X, const SpectralSigmaOptions& options = {});

struct KernelDiagnosticsOptions {
  double cutoff = 5.0;         ///< θ = cutoff · σ (thesis 6.1).
  int iterations = 60;         ///< Power / inverse iterations for the extreme eigenvalues.
  bool condition = true;       ///< Estimate the condition number (needs a sparse factorization).
};

struct KernelDiagnostics {
  double sigma = 0.0;
  /// Row sums of K (Σ_j k(x_i, x_j), Figs 3.1, 3.3) over all rows and over the "inner" rows, at
  /// least θ from the point set's bounding box (where the sum should be flat: 2πσ²/area-per-point).
  double rowSumMin = 0.0, rowSumMax = 0.0, rowSumMean = 0.0;
  double innerRowSumMin = 0.0, innerRowSumMax = 0.0, innerRowSumMean = 0.0;
  double innerRowSumSpread = 0.0;  ///< (max − min) / mean over inner rows; small = even sampling
  Index innerRows = 0;
  double lambdaMax = 0.0, lambdaMin = 0.0;
  double conditionEstimate = 0.0;  ///< λmax / λmin; +∞ when K is not numerically positive definite
  bool positiveDefinite = true;
  double seconds = 0.0;
};

/// Assembles K_ij = exp(−|x_i − x_j|² / 2σ²) for |x_i − x_j| ≤ θ and reports its row sums and an
/// estimate of its condition number (power iteration for λmax, inverse iteration through a sparse
/// LDLᵀ factorization for λmin), so that a bad σ is visible before binding.
KernelDiagnostics kernelDiagnostics(const Points& X, double sigma, const KernelDiagnosticsOptions& options = {});

}  // namespace kc::sampling
