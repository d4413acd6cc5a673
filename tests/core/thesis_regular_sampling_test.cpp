// Reproduces thesis section 3.3.1 (regular sampling): dual kernel functions of a 41×41 grid
// (σ = 3T/π, eq. 3.28) evaluated on a 201×201 background grid over the central quarter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>
#include <numbers>

#include "kc/core/kernel/interpolator.h"
#include "kc/core/metrics.h"

namespace kc {
namespace {

struct RegularSetup {
  double T = 1.0;
  Points X;       // 41×41 grid samples over [−20T, 20T]²
  Points Pbg;     // 201×201 background points over the central quarter
  Points Pgrid;   // grid samples inside the evaluation area
  std::vector<Index> gridIndex;  // their sample indices
  GaussianKernel kernel;
};

RegularSetup makeSetup(double T) {
  RegularSetup s;
  s.T = T;
  const int n = 41, nb = 201;
  s.X.resize(n * n, 2);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) s.X.row(r * n + c) << (c - 20) * T, (r - 20) * T;
  // Centred on the origin, as the thesis's figures imply (the reproduction error of the plain
  // form depends on the origin: Σ a_i x_i − x changes by c·(Σ a_i − 1) under a shift by c).
  const double lo = -10 * T, hi = 10 * T;  // central quarter of [−20T, 20T]²
  s.Pbg.resize(nb * nb, 2);
  for (int r = 0; r < nb; ++r)
    for (int c = 0; c < nb; ++c) s.Pbg.row(r * nb + c) << lo + (hi - lo) * c / (nb - 1), lo + (hi - lo) * r / (nb - 1);
  for (int r = 10; r <= 30; ++r)
    for (int c = 10; c <= 30; ++c) s.gridIndex.push_back(r * n + c);
  s.Pgrid.resize(static_cast<Index>(s.gridIndex.size()), 2);
  for (std::size_t k = 0; k < s.gridIndex.size(); ++k) s.Pgrid.row(static_cast<Index>(k)) = s.X.row(s.gridIndex[k]);
  s.kernel = GaussianKernel::forSpacing(3.0 * T / std::numbers::pi, T);
  return s;
}

struct Figures {
  double partitionOfUnity = 0.0;   // max |a(x)ᵀ1 − 1|
  double reproductionMax = 0.0;    // max D(x) = |Σ a_i(x) x_i − x|_∞ / T
  double reproductionMean = 0.0;
  double reproductionMedian = 0.0;
  double lagrangeSum = 0.0;        // Σ_i Σ_j |a_i(x_j) − δ_ij| over grid points j in the area
};

Figures measure(const RegularSetup& s, InterpMode mode, bool withLagrange) {
  KernelInterpolator interp;
  const InterpolatorReport rep = interp.compute(s.X, s.kernel, mode);
  EXPECT_EQ(rep.status, SolveStatus::Ok) << rep.advice;
  Figures f;
  // The dual functions interpolate any W linearly, so Σ a_j(x)·1 and Σ a_j(x) x_j are the
  // interpolants of the columns [1 x y].
  Weights W(s.X.rows(), 3);
  W.col(0).setOnes();
  W.rightCols<2>() = s.X;
  const Weights w = interp.evaluate(interp.solve(W), s.Pbg);
  f.partitionOfUnity = partitionOfUnityError(w.leftCols<1>());
  Eigen::ArrayXd D = (w.rightCols<2>() - s.Pbg).cwiseAbs().rowwise().maxCoeff().array() / s.T;
  f.reproductionMax = D.maxCoeff();
  f.reproductionMean = D.mean();
  std::vector<double> sorted(D.begin(), D.end());
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  f.reproductionMedian = sorted[sorted.size() / 2];
  if (withLagrange) {
    const Index n = s.X.rows();
    const Weights A = interp.evaluate(interp.solve(Weights::Identity(n, n)), s.Pgrid);
    for (Index k = 0; k < A.rows(); ++k)
      for (Index i = 0; i < n; ++i) f.lagrangeSum += std::abs(A(k, i) - (i == s.gridIndex[static_cast<std::size_t>(k)] ? 1.0 : 0.0));
  }
  return f;
}

// Thesis 3.3.1: partition of unity 2.2e-4; reproduction D max 3.4e-3, mean 0.60e-3, median
// 0.33e-3; Lagrange deviation sum 5.1e-11. Tolerance: 20% of each published figure; the
// Lagrange sum is round-off, so only its order of magnitude is checked.
TEST(ThesisRegularSampling, ThesisModeMatchesPublishedFigures) {
  const Figures f = measure(makeSetup(1.0), InterpMode::Thesis, true);
  std::printf("thesis mode: PoU %.3g  repro max %.3g mean %.3g median %.3g  Lagrange sum %.3g\n",
              f.partitionOfUnity, f.reproductionMax, f.reproductionMean, f.reproductionMedian, f.lagrangeSum);
  EXPECT_NEAR(f.partitionOfUnity, 2.2e-4, 0.2 * 2.2e-4);
  EXPECT_NEAR(f.reproductionMax, 3.4e-3, 0.2 * 3.4e-3);
  EXPECT_NEAR(f.reproductionMean, 0.60e-3, 0.2 * 0.60e-3);
  EXPECT_NEAR(f.reproductionMedian, 0.33e-3, 0.2 * 0.33e-3);
  EXPECT_LT(f.lagrangeSum, 5e-10);  // thesis: 5.1e-11 (round-off level); 10× margin
}

TEST(ThesisRegularSampling, ThesisModeIsScaleInvariant) {
  // "We experiment with T = 2 and T = 0.5 and get practically identical results."
  const Figures a = measure(makeSetup(0.5), InterpMode::Thesis, false);
  const Figures b = measure(makeSetup(2.0), InterpMode::Thesis, false);
  EXPECT_NEAR(a.partitionOfUnity, b.partitionOfUnity, 1e-3 * b.partitionOfUnity);
  EXPECT_NEAR(a.reproductionMax, b.reproductionMax, 1e-3 * b.reproductionMax);
}

TEST(ThesisRegularSampling, ExactModeIsExact) {
  const Figures f = measure(makeSetup(1.0), InterpMode::Exact, true);
  std::printf("exact mode: PoU %.3g  repro max %.3g  Lagrange sum %.3g\n", f.partitionOfUnity, f.reproductionMax,
              f.lagrangeSum);
  EXPECT_LE(f.partitionOfUnity, 1e-12);
  EXPECT_LE(f.reproductionMax, 1e-12);
  EXPECT_LT(f.lagrangeSum, 5e-10);
}

}  // namespace
}  // namespace kc
