// Kernel scale: σ = 3T/π (3.28), spectral choice (Fig 6.10), row sums and conditioning (3.3.1-3.3.2).
#include <gtest/gtest.h>

#include "test_shapes.h"

#include <cmath>
#include <numbers>

#include "kc/sampling/blue_noise.h"
#include "kc/sampling/sigma.h"

namespace kc::sampling {
namespace {

using test::squareGrid;

TEST(Sigma, RuleOfEquation328) {
  EXPECT_DOUBLE_EQ(sigmaFromSpacing(1.0), 3.0 / std::numbers::pi);
  EXPECT_NEAR(suggestSigma(squareGrid(10, 2.0)), 6.0 / std::numbers::pi, 1e-12);
  SampleSet S;
  S.X = squareGrid(5, 3.0);
  EXPECT_NEAR(suggestSigma(S), 9.0 / std::numbers::pi, 1e-12);
  EXPECT_THROW(suggestSigma(Points::Zero(1, 2)), std::invalid_argument);
}

/// Thesis 3.3.1 on an n×n grid, T = 1, σ = 3T/π: inner row sums 18/π (3.30), condition number ~1e3.
void expectGridRowSumsAndConditionOfThesis331(Index n) {
  const Points X = squareGrid(n, 1.0);
  const KernelDiagnostics d = kernelDiagnostics(X, sigmaFromSpacing(1.0));
  ASSERT_GT(d.innerRows, 100);
  // 18/π up to the kernel's truncation at 5σ (a relative tail of ~4e-6 · 12.5).
  EXPECT_NEAR(d.innerRowSumMean, 18.0 / std::numbers::pi, 1e-4);
  EXPECT_LT(d.innerRowSumSpread, 1e-9);
  EXPECT_LT(d.rowSumMin, 0.6 * d.innerRowSumMean) << "sums fall off at the grid's border (Fig 3.1)";
  EXPECT_TRUE(d.positiveDefinite);
  EXPECT_GT(d.conditionEstimate, 1e3);
  EXPECT_LT(d.conditionEstimate, 1e4);
}

TEST(Sigma, GridRowSumsAndConditionMatchThesis331) { expectGridRowSumsAndConditionOfThesis331(31); }

TEST(SigmaSlow, GridRowSumsAndConditionMatchThesis331OnALargerGrid) { expectGridRowSumsAndConditionOfThesis331(61); }

TEST(Sigma, BlueNoiseSetOfThesis332) {
  // 1024 blue-noise points on [−30, 30]², σ = 2.5: row sums fluctuate a little inside (Fig 3.3),
  // condition number ≈ 2.3e5 in the thesis (Balzer et al.'s points; ours are similar).
  const Points X = blueNoiseRectangle(1024, Rect{-30, -30, 30, 30}, 1);
  const KernelDiagnostics d = kernelDiagnostics(X, 2.5);
  EXPECT_GT(d.innerRowSumSpread, 1e-4);
  EXPECT_LT(d.innerRowSumSpread, 0.05);
  EXPECT_GT(d.conditionEstimate, 1e4);
  EXPECT_LT(d.conditionEstimate, 1e6);
  // Larger σ: flatter sums, much worse conditioning (the trade-off of 3.2).
  const KernelDiagnostics wide = kernelDiagnostics(X, 3.5);
  EXPECT_LT(wide.innerRowSumSpread, d.innerRowSumSpread);
  EXPECT_GT(wide.conditionEstimate, 100.0 * d.conditionEstimate);
}

/// Spectral σ (Fig 6.10) on an n×n grid (T = 1) and on n² blue-noise points over [0, n]².
void expectSpectralChoiceAgreesWithRuleOnAGridAndIsLargerOnBlueNoise(Index n) {
  // The finite window broadens the grid's first peak by up to 4π/L, so the gap ends a little early.
  const double T = 1.0;
  const SpectralSigma g = spectralSigma(squareGrid(n, T));
  EXPECT_NEAR(g.sigma, sigmaFromSpacing(T), 0.08 * sigmaFromSpacing(T));
  EXPECT_NEAR(g.gapOmega, 2.0 * std::numbers::pi / T, 4.0 * std::numbers::pi / double(n));
  const double L = double(n) * 2.0 / 3.0;
  const Points B = blueNoiseRectangle(Index(L * L), Rect{0, 0, L, L}, 2);
  const SpectralSigma b = spectralSigma(B);
  EXPECT_GT(b.sigma, suggestSigma(B));
  EXPECT_LT(b.sigma, 2.0 * suggestSigma(B));
}

TEST(Sigma, SpectralChoiceAgreesWithRuleOnAGridAndIsLargerOnBlueNoise) {
  expectSpectralChoiceAgreesWithRuleOnAGridAndIsLargerOnBlueNoise(30);
}

TEST(SigmaSlow, SpectralChoiceAgreesWithRuleOnALargerGridAndBlueNoise) {
  expectSpectralChoiceAgreesWithRuleOnAGridAndIsLargerOnBlueNoise(60);
}

TEST(Sigma, TooLargeSigmaIsVisibleInTheReport) {
  const KernelDiagnostics d = kernelDiagnostics(squareGrid(20, 1.0), 3.0);
  EXPECT_TRUE(!d.positiveDefinite || d.conditionEstimate > 1e12);
  EXPECT_THROW(kernelDiagnostics(squareGrid(3, 1.0), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace kc::sampling
