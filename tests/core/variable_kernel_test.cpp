// The variable-width (Gibbs) kernel of graded samplings: it is the constant Gaussian when the
// widths agree, its matrices are positive definite for any width field, its gradient is right,
// and the interpolator reproduces exactly with it.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <memory>
#include <random>

#include "kc/core/kernel/interpolator.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/sizing.h"
#include "random_point.h"

namespace kc {
namespace {

/// A width field that shrinks to 1 near (50, 50) from 8 elsewhere.
std::shared_ptr<const SizingField> shrinkingWidth() {
  Points P(3, 2);
  P << 50, 50, 52, 50, 54, 51;
  return std::make_shared<const SizingField>(8.0, 0.3, P, Eigen::Vector3d(1.0, 1.2, 1.5));
}

TEST(VariableKernel, EqualWidthsGiveTheConstantKernel) {
  GaussianKernel k = GaussianKernel::forSpacing(4.0, 4.0);
  k.width = shrinkingWidth();
  ASSERT_TRUE(k.variable());
  GaussianKernel c = GaussianKernel::forSpacing(4.0, 4.0);
  for (double r2 : {0.0, 1.0, 9.0, 100.0, 399.0, 401.0}) EXPECT_EQ(k(r2, 4.0, 4.0), c(r2)) << r2;
  EXPECT_EQ(k(2.0, 1.5, 3.0), k(2.0, 3.0, 1.5));  // symmetric to the bit
}

TEST(VariableKernel, MatrixIsPositiveDefiniteForAnyWidths) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    // Random points (some close together) and random seed sizes: σ varies by up to 8× over them.
    const Index n = 60;
    Points X(n, 2);
    for (Index i = 0; i < n; ++i) X.row(i) << 100 * u(rng), 100 * u(rng);
    Points P(4, 2);
    Eigen::VectorXd H(4);
    for (Index s = 0; s < 4; ++s) {
      P.row(s) << 100 * u(rng), 100 * u(rng);
      H(s) = 1.0 + 7.0 * u(rng);
    }
    GaussianKernel k = GaussianKernel::forSpacing(10.0, 10.0);
    k.cutoffFactor = 1e3;  // no truncation: the theorem is about the full kernel
    k.width = std::make_shared<const SizingField>(8.0, 0.5, P, H);
    const Eigen::MatrixXd K = Eigen::MatrixXd(assembleKernelMatrix(X, k));
    EXPECT_LE((K - K.transpose()).cwiseAbs().maxCoeff(), 0.0);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K);
    EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-12 * eig.eigenvalues().maxCoeff()) << "trial " << trial;
    // A (rank-deficient in floating point) sum of squares is ≥ 0: check a random quadratic form too.
    const Eigen::VectorXd a = Eigen::VectorXd::Random(n);
    EXPECT_GE(a.dot(K * a), -1e-12 * a.squaredNorm() * eig.eigenvalues().maxCoeff());
  }
}

TEST(VariableKernel, GradientMatchesFiniteDifferences) {
  GaussianKernel k = GaussianKernel::forSpacing(6.0, 6.0);
  k.width = shrinkingWidth();
  const Vec2 y(53, 47);
  const double sy = k.widthAt(y);
  for (const Vec2& x : {Vec2(51, 52), Vec2(58, 49), Vec2(49, 41)}) {
    Vec2 g;
    const double sx = k.widthAt(x, g);
    const double v = k((x - y).squaredNorm(), sx, sy);
    ASSERT_GT(v, 0.0);
    const Vec2 analytic = v * k.gradientFactor(x - y, sx, g, sy);
    const double e = 1e-6;
    for (int d = 0; d < 2; ++d) {
      Vec2 dx = Vec2::Zero();
      dx(d) = e;
      const double fp = k((x + dx - y).squaredNorm(), k.widthAt(x + dx), sy), fm = k((x - dx - y).squaredNorm(), k.widthAt(x - dx), sy);
      EXPECT_NEAR(analytic(d), (fp - fm) / (2 * e), 1e-6 * (1.0 + std::abs(analytic(d)))) << "at " << x.transpose() << " d " << d;
    }
  }
}

TEST(VariableKernel, TruncatedMatrixAndRowsHoldEveryNonZeroPair) {
  // Graded points: dense (0.3–1 px apart) around the shrinking width's centre, 8 px apart far from
  // it, where the search skips whole cells of narrow samples. Every pair the kernel does not
  // truncate must be in K and in the query rows, with the kernel's value to the bit.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto width = shrinkingWidth();
  std::vector<Vec2> pts;
  while (pts.size() < 1500) {
    const Vec2 p(160 * u(rng) - 30, 160 * u(rng) - 30);
    if (u(rng) * 8.0 < 1.0 / (*width)(p) * 8.0 * u(rng) + 0.05) pts.push_back(p);
  }
  Points X(static_cast<Index>(pts.size()), 2), Q(200, 2);
  for (std::size_t i = 0; i < pts.size(); ++i) X.row(static_cast<Index>(i)) = pts[i].transpose();
  for (Index q = 0; q < Q.rows(); ++q) Q.row(q) << 40 + 25 * u(rng), 40 + 25 * u(rng);
  GaussianKernel k = GaussianKernel::forSpacing(7.0, 8.0);
  k.width = width;
  const Eigen::MatrixXd K = Eigen::MatrixXd(assembleKernelMatrix(X, k));
  const Eigen::MatrixXd R = Eigen::MatrixXd(kernelRows(X, Q, k));
  Index nonZeros = 0, narrowPairs = 0;
  for (Index i = 0; i < X.rows(); ++i)
    for (Index j = 0; j < X.rows(); ++j) {
      const double v = k((X.row(i) - X.row(j)).squaredNorm(), k.widthAt(X.row(i)), k.widthAt(X.row(j)));
      ASSERT_EQ(K(i, j), v) << i << ", " << j;
      nonZeros += v != 0.0;
      narrowPairs += v != 0.0 && k.widthAt(X.row(i)) < 2.0 && k.widthAt(X.row(j)) > 5.0;
    }
  for (Index q = 0; q < Q.rows(); ++q)
    for (Index j = 0; j < X.rows(); ++j)
      ASSERT_EQ(R(q, j), k((Q.row(q) - X.row(j)).squaredNorm(), k.widthAt(Q.row(q)), k.widthAt(X.row(j)))) << q << ", " << j;
  EXPECT_GT(narrowPairs, 0);  // the set-up has the pairs of a narrow and a wide sample that reach far
  EXPECT_LT(nonZeros, X.rows() * X.rows() / 4);  // and it is truncated
}

TEST(VariableKernel, ExactInterpolationReproducesLinearFunctions) {
  // Samples on a jittered grid, denser near the shrinking width's centre.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  std::vector<Vec2> pts;
  const auto width = shrinkingWidth();
  for (double y = 0; y <= 100; y += 0.5)
    for (double x = 0; x <= 100; x += 0.5) {
      const Vec2 p(x, y);
      const double h = (*width)(p);
      // Keep a point where it falls on the local spacing's lattice.
      if (std::fmod(x, std::max(0.5, std::round(h * 2) / 2)) == 0.0 && std::fmod(y, std::max(0.5, std::round(h * 2) / 2)) == 0.0)
        pts.push_back(p + test::randomPoint(u, rng) * h);
    }
  Points X(static_cast<Index>(pts.size()), 2);
  for (std::size_t i = 0; i < pts.size(); ++i) X.row(static_cast<Index>(i)) = pts[i].transpose();
  GaussianKernel k = GaussianKernel::forSpacing(8.0 * 3.0 / 3.14159, 8.0);
  k.width = width;
  KernelInterpolator interp;
  ASSERT_EQ(interp.compute(X, k, InterpMode::Exact).status, SolveStatus::Ok);
  // W = [1, x, y]: reproduced at arbitrary points.
  Weights W(X.rows(), 3);
  W.col(0).setOnes();
  W.col(1) = X.col(0);
  W.col(2) = X.col(1);
  const KernelCoefficients c = interp.solve(W);
  Points Q(4, 2);
  Q << 50.3, 50.2, 20, 70, 55.5, 48.1, 90, 10;
  const Weights V = interp.evaluate(c, Q);
  for (Index q = 0; q < Q.rows(); ++q) {
    EXPECT_NEAR(V(q, 0), 1.0, 1e-9);
    EXPECT_NEAR(V(q, 1), Q(q, 0), 1e-7);
    EXPECT_NEAR(V(q, 2), Q(q, 1), 1e-7);
  }
  // Any data is interpolated at the samples (the evaluation's kernel rows are K's rows).
  const Weights R = Weights::Random(X.rows(), 2);
  const Weights at = interp.evaluate(interp.solve(R), X);
  EXPECT_LE((at - R).cwiseAbs().maxCoeff(), 1e-8);
  // The gradient of the reproduced x is (1, 0).
  Weights Gx, Gy;
  interp.evaluateGradient(c, Q, Gx, Gy);
  for (Index q = 0; q < Q.rows(); ++q) {
    EXPECT_NEAR(Gx(q, 1), 1.0, 1e-6);
    EXPECT_NEAR(Gy(q, 1), 0.0, 1e-6);
  }
}

}  // namespace
}  // namespace kc
