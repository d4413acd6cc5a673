#include "kc/sampling/sigma.h"

#include "kc/core/kernel/kernel_matrix.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "kc/core/kernel/kernel_matrix.h"

namespace kc::sampling {

double sigmaFromSpacing(double T) { return 3.0 * T / std::numbers::pi; }

double suggestSigma(const Points& X) {
  if (X.rows() < 2) throw std::invalid_argument("suggestSigma: need at least two samples");
  return sigmaFromSpacing(meanNearestNeighbourSpacing(X));
}

double suggestSigma(const SampleSet& S) { return suggestSigma(S.X); }

double suggestSigma(const Points& X, const SizingField& sizing) {
  if (!sizing.graded()) return suggestSigma(X);
  if (X.rows() < 2) throw std::invalid_argument("suggestSigma: need at least two samples");
  const Eigen::VectorXd nn = nearestNeighbourDistances(X), h = sizing.at(X);
  double sum = 0.0;
  Index n = 0;
  for (Index i = 0; i < X.rows(); ++i)
    if (std::isfinite(nn(i))) sum += nn(i) / h(i), ++n;
  if (n == 0) throw std::invalid_argument("suggestSigma: need at least two samples");
  return sigmaFromSpacing(sum / static_cast<double>(n) * sizing.hMax());
}

SpectralSigma spectralSigma(const Points& X, const SpectralSigmaOptions& options) {
  SpectralSigma result;
  if (X.rows() < 2) return result;
  result.spectrum = radialPowerSpectrum(X, options.spectrum);
  const RadialSpectrum& s = result.spectrum;
  // The Hann window's main lobe around ω = 0 is 4π/L wide; skip twice that.
  const Eigen::RowVector2d ext = X.colwise().maxCoeff() - X.colwise().minCoeff();
  const double L = std::max(ext.minCoeff(), 1e-12);
  const double omegaStart = 8.0 * std::numbers::pi / L;
  for (Index b = 0; b < s.omega.size(); ++b) {
    if (s.omega(b) < omegaStart || s.power(b) < options.gapLevel) continue;
    // Interpolate the crossing between this bin and the previous one.
    double w = s.omega(b);
    if (b > 0 && s.omega(b - 1) >= omegaStart) {
      const double p0 = s.power(b - 1), p1 = s.power(b);
      if (p1 > p0) w = s.omega(b - 1) + (options.gapLevel - p0) / (p1 - p0) * (s.omega(b) - s.omega(b - 1));
    }
    result.gapOmega = w;
    result.sigma = std::sqrt(-2.0 * std::log(options.ratio)) / w;
    break;
  }
  return result;
}

KernelDiagnostics kernelDiagnostics(const Points& X, double sigma, const KernelDiagnosticsOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (!(sigma > 0.0) || !std::isfinite(sigma)) throw std::invalid_argument("kernelDiagnostics: sigma must be positive");
  KernelDiagnostics d;
  d.sigma = sigma;
  const Index n = X.rows();
  if (n == 0) return d;
  const double theta = options.cutoff * sigma;
  // The same truncated kernel matrix the interpolator factorizes (unit scale, thesis 3.5–3.6, 6.1).
  GaussianKernel kernel;
  kernel.sigma = sigma;
  kernel.cutoffFactor = options.cutoff;
  const SparseMatrix K = assembleKernelMatrix(X, kernel);
  const Eigen::VectorXd rowSum = K * Eigen::VectorXd::Ones(n);

  d.rowSumMin = rowSum.minCoeff();
  d.rowSumMax = rowSum.maxCoeff();
  d.rowSumMean = rowSum.mean();
  const Eigen::RowVector2d lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  double mn = std::numeric_limits<double>::infinity(), mx = -mn, sum = 0.0;
  for (Index i = 0; i < n; ++i) {
    const double edge = std::min({X(i, 0) - lo(0), hi(0) - X(i, 0), X(i, 1) - lo(1), hi(1) - X(i, 1)});
    if (edge < theta) continue;
    mn = std::min(mn, rowSum(i));
    mx = std::max(mx, rowSum(i));
    sum += rowSum(i);
    ++d.innerRows;
  }
  if (d.innerRows > 0) {
    d.innerRowSumMin = mn;
    d.innerRowSumMax = mx;
    d.innerRowSumMean = sum / static_cast<double>(d.innerRows);
    d.innerRowSumSpread = (mx - mn) / d.innerRowSumMean;
  }

  if (options.condition) {
    // λmax: power iteration from a fixed start vector.
    Eigen::VectorXd v = Eigen::VectorXd::Ones(n).normalized(), w;
    for (int it = 0; it < options.iterations; ++it) {
      w = K * v;
      d.lambdaMax = v.dot(w);
      v = w.normalized();
    }
    // λmin: inverse iteration through LDLᵀ.
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(K);
    if (ldlt.info() != Eigen::Success || (ldlt.vectorD().array() <= 0.0).any()) {
      d.positiveDefinite = false;
      d.conditionEstimate = std::numeric_limits<double>::infinity();
    } else {
      v = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0).normalized();
      double mu = 0.0;
      for (int it = 0; it < options.iterations; ++it) {
        w = ldlt.solve(v);
        mu = v.dot(w);  // ≈ 1/λmin
        v = w.normalized();
      }
      d.lambdaMin = mu > 0.0 ? 1.0 / mu : 0.0;
      d.conditionEstimate = d.lambdaMin > 0.0 ? d.lambdaMax / d.lambdaMin : std::numeric_limits<double>::infinity();
    }
  }
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return d;
}

}  // namespace kc::sampling
