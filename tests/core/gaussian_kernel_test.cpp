#include "kc/core/kernel/gaussian_kernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace kc {
namespace {

TEST(GaussianKernel, ValueAndCutoff) {
  GaussianKernel k;
  k.sigma = 2.0;
  k.scale = 3.0;
  EXPECT_DOUBLE_EQ(k.cutoff(), 10.0);
  EXPECT_DOUBLE_EQ(k(0.0), 3.0);
  EXPECT_DOUBLE_EQ(k(4.0), 3.0 * std::exp(-0.5));  // r = σ
  EXPECT_GT(k(100.0), 0.0);                        // r = θ exactly: kept
  EXPECT_EQ(k(100.0 + 1e-9), 0.0);                 // beyond θ: zero
}

TEST(GaussianKernel, ForSpacingNormalizesRowSumsOnAGrid) {
  // (3.30): on an infinite grid of period T with σ = 3T/π, Σ_j k(x, x_j) is constant; forSpacing
  // scales it to 1. Check at grid points and between them, far from the border of a finite grid.
  for (double T : {0.5, 1.0, 4.0}) {
    const GaussianKernel k = GaussianKernel::forSpacing(3.0 * T / std::numbers::pi, T);
    for (const auto& [ox, oy] : {std::pair{0.0, 0.0}, std::pair{0.5, 0.5}, std::pair{0.3, 0.1}}) {
      double sum = 0.0;
      for (int i = -20; i <= 20; ++i)
        for (int j = -20; j <= 20; ++j) {
          const double dx = (i - ox) * T, dy = (j - oy) * T;
          sum += k(dx * dx + dy * dy);
        }
      // Aliasing ~1e-8 (3.27) plus the truncated tail at 5σ (~4e-6 of the mass).
      EXPECT_NEAR(sum, 1.0, 1e-5) << "T=" << T;
    }
  }
}

TEST(GaussianKernel, ForSpacingRejectsBadInput) {
  EXPECT_THROW(GaussianKernel::forSpacing(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(GaussianKernel::forSpacing(1.0, -1.0), std::invalid_argument);
  EXPECT_THROW(GaussianKernel::forSpacing(std::nan(""), 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace kc
