#include "kc/core/kernel/interpolator.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "kc/core/parallel.h"
#include "point_problems.h"

namespace kc {
namespace {

using test::jitteredGrid;
using test::kernelFor;
using test::randomPointsIn;
using test::randomWeights;

class InterpolatorModes : public ::testing::TestWithParam<InterpMode> {};

TEST_P(InterpolatorModes, LagrangePropertyAtSamples) {
  // w(x_j) = W_j (3.4, 3.21): the interpolant takes the prescribed weights at every sample.
  const Points X = jitteredGrid(20, 3.0, 0.2, 11, Vec2(100.0, 250.0));
  KernelInterpolator interp;
  ASSERT_EQ(interp.compute(X, kernelFor(3.0), GetParam()).status, SolveStatus::Ok);
  const Weights W = randomWeights(X.rows(), 5, 12);
  const Weights w = interp.evaluate(interp.solve(W), X);
  EXPECT_LE((w - W).cwiseAbs().maxCoeff(), 1e-10);
}

TEST_P(InterpolatorModes, ThesisModeMatchesDenseInverse) {
  // U = K⁻¹(W − P B) against a dense reference solve of the same (augmented) system.
  const Points X = jitteredGrid(12, 1.0, 0.25, 13);
  KernelInterpolator interp;
  ASSERT_EQ(interp.compute(X, kernelFor(1.0), GetParam()).status, SolveStatus::Ok);
  const Weights W = randomWeights(X.rows(), 3, 14);
  const KernelCoefficients coef = interp.solve(W);
  const Index n = X.rows();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + 3, n + 3);
  A.topLeftCorner(n, n) = Eigen::MatrixXd(assembleKernelMatrix(X, kernelFor(1.0)));
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + 3, 3);
  rhs.topRows(n) = W;
  if (GetParam() == InterpMode::Exact) {
    A.block(0, n, n, 1).setOnes();
    A.block(0, n + 1, n, 2) = X;
    A.block(n, 0, 3, n) = A.block(0, n, n, 3).transpose();
  } else {
    A.bottomRightCorner(3, 3).setIdentity();
  }
  const Eigen::MatrixXd ref = A.fullPivLu().solve(rhs);
  EXPECT_LE((coef.U - ref.topRows(n)).cwiseAbs().maxCoeff(), 1e-8 * ref.cwiseAbs().maxCoeff());
  EXPECT_LE((coef.B - ref.bottomRows(3)).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + ref.bottomRows(3).cwiseAbs().maxCoeff()));
}

TEST_P(InterpolatorModes, GradientMatchesFiniteDifferences) {
  const Points X = jitteredGrid(15, 2.0, 0.2, 15);
  KernelInterpolator interp;
  ASSERT_EQ(interp.compute(X, kernelFor(2.0), GetParam()).status, SolveStatus::Ok);
  const KernelCoefficients coef = interp.solve(randomWeights(X.rows(), 4, 16));
  const Points P = randomPointsIn(50, 2.0, 26.0, 17);
  Weights gx, gy;
  interp.evaluateGradient(coef, P, gx, gy);
  const double h = 1e-5;
  Points dx = Points::Zero(P.rows(), 2), dy = Points::Zero(P.rows(), 2);
  dx.col(0).setConstant(h);
  dy.col(1).setConstant(h);
  const Weights fdx = (interp.evaluate(coef, P + dx) - interp.evaluate(coef, P - dx)) / (2 * h);
  const Weights fdy = (interp.evaluate(coef, P + dy) - interp.evaluate(coef, P - dy)) / (2 * h);
  const double scale = std::max(gx.cwiseAbs().maxCoeff(), gy.cwiseAbs().maxCoeff());
  EXPECT_LE((gx - fdx).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_LE((gy - fdy).cwiseAbs().maxCoeff(), 1e-6 * scale);
}

TEST_P(InterpolatorModes, ThreadCountDoesNotChangeResults) {
  const Points X = jitteredGrid(40, 1.0, 0.2, 18);
  const Weights W = randomWeights(X.rows(), 6, 19);
  const Points P = randomPointsIn(2000, 0.0, 39.0, 20);
  Weights w[2], gx[2], gy[2];
  for (int t : {1, 2}) {
    ScopedThreadCount threads(t);
    KernelInterpolator interp;
    ASSERT_EQ(interp.compute(X, kernelFor(1.0), GetParam()).status, SolveStatus::Ok);
    const KernelCoefficients coef = interp.solve(W);
    w[t - 1] = interp.evaluate(coef, P);
    interp.evaluateGradient(coef, P, gx[t - 1], gy[t - 1]);
  }
  EXPECT_TRUE(w[0] == w[1]);  // bit-identical
  EXPECT_TRUE(gx[0] == gx[1]);
  EXPECT_TRUE(gy[0] == gy[1]);
}

INSTANTIATE_TEST_SUITE_P(Interpolator, InterpolatorModes, ::testing::Values(InterpMode::Exact, InterpMode::Thesis),
                         [](const auto& info) { return info.param == InterpMode::Exact ? "Exact" : "Thesis"; });

TEST(Interpolator, ExactModeReproducesLinearFunctionsOnRandomSamples) {
  // Linear precision of the augmented interpolant: any W whose columns are affine in x is
  // reproduced everywhere, not only at the samples (irregular samples, far from the origin).
  const Points X = jitteredGrid(25, 4.0, 0.35, 21, Vec2(500.0, 300.0));
  KernelInterpolator interp;
  ASSERT_EQ(interp.compute(X, kernelFor(4.0), InterpMode::Exact).status, SolveStatus::Ok);
  Weights W(X.rows(), 3);
  W.col(0).setOnes();
  W.col(1) = 0.3 - 0.01 * X.col(0).array() + 0.02 * X.col(1).array();
  W.col(2) = X.col(1);
  const Points P = randomPointsIn(3000, 300.0, 700.0, 22);  // also outside the samples
  const Weights w = interp.evaluate(interp.solve(W), P);
  EXPECT_LE((w.col(0).array() - 1.0).abs().maxCoeff(), 1e-12);
  EXPECT_LE((w.col(1).array() - (0.3 - 0.01 * P.col(0).array() + 0.02 * P.col(1).array())).abs().maxCoeff(), 1e-12);
  EXPECT_LE((w.col(2) - P.col(1)).cwiseAbs().maxCoeff(), 1e-12 * 700.0);
}

TEST(Interpolator, ThesisModeIsOnlyApproximatelyLinear) {
  // Guards the mode switch: the plain form is not exact for constants near the border.
  const Points X = jitteredGrid(25, 4.0, 0.35, 21);
  KernelInterpolator interp;
  ASSERT_EQ(interp.compute(X, kernelFor(4.0), InterpMode::Thesis).status, SolveStatus::Ok);
  const KernelCoefficients coef = interp.solve(Weights::Ones(X.rows(), 1));
  EXPECT_EQ(coef.B.cwiseAbs().maxCoeff(), 0.0);
  const Weights w = interp.evaluate(coef, randomPointsIn(500, 0.0, 96.0, 23));
  EXPECT_GT((w.array() - 1.0).abs().maxCoeff(), 1e-6);
}

TEST(Interpolator, JacobianMatchesFiniteDifferencesOfDeformation) {
  const Points X = jitteredGrid(15, 2.0, 0.2, 24);
  const int m = 4;
  KernelInterpolator interp;
  ASSERT_EQ(interp.compute(X, kernelFor(2.0), InterpMode::Exact).status, SolveStatus::Ok);
  const KernelCoefficients coef = interp.solve(randomWeights(X.rows(), m, 25));
  std::mt19937 rng(26);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Affine2> T(m);
  for (auto& t : T) {
    const double a = u(rng);
    t << std::cos(a), -std::sin(a), 5 * u(rng), std::sin(a), std::cos(a), 5 * u(rng);
    t.leftCols<2>() *= 1.0 + 0.2 * u(rng);
  }
  // f(x) = Σ_i w_i(x) T_i x̃ (3.37).
  auto f = [&](const Vec2& x) {
    Points p(1, 2);
    p.row(0) = x.transpose();
    const Weights w = interp.evaluate(coef, p);
    Vec2 out = Vec2::Zero();
    for (int i = 0; i < m; ++i) out += w(0, i) * (T[i] * Eigen::Vector3d(x.x(), x.y(), 1.0));
    return out;
  };
  const Points P = randomPointsIn(20, 4.0, 24.0, 27);
  Weights w = interp.evaluate(coef, P), gx, gy;
  interp.evaluateGradient(coef, P, gx, gy);
  for (Index p = 0; p < P.rows(); ++p) {
    const Vec2 x = P.row(p).transpose();
    const Eigen::Matrix2d J = deformationJacobian(x, w.row(p).transpose(), gx.row(p).transpose(), gy.row(p).transpose(), T);
    const double h = 1e-5;
    Eigen::Matrix2d Jfd;
    Jfd.col(0) = (f(x + Vec2(h, 0)) - f(x - Vec2(h, 0))) / (2 * h);
    Jfd.col(1) = (f(x + Vec2(0, h)) - f(x - Vec2(0, h))) / (2 * h);
    EXPECT_LE((J - Jfd).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + J.cwiseAbs().maxCoeff())) << "point " << p;
  }
}

TEST(Interpolator, DeformationJacobianOfIdenticalHandlesIsTheirLinearPart) {
  // All T_i equal ⇒ f(x) = T x when Σ w_i = 1, so J = A whatever ∇w is as long as Σ ∇w_i = 0.
  Affine2 T;
  T << 1.2, -0.3, 4.0, 0.5, 0.9, -2.0;
  const Eigen::VectorXd w = Eigen::Vector3d(0.2, 0.5, 0.3);
  const Eigen::VectorXd gx = Eigen::Vector3d(0.1, -0.4, 0.3), gy = Eigen::Vector3d(-0.2, 0.1, 0.1);
  const Eigen::Matrix2d J = deformationJacobian(Vec2(3.0, -1.0), w, gx, gy, {T, T, T});
  EXPECT_LE((J - T.leftCols<2>()).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_THROW(deformationJacobian(Vec2(0, 0), w, gx, gy, {T, T}), std::invalid_argument);
}

TEST(Interpolator, SigmaTooLargeIsReportedNotThrown) {
  const Points X = jitteredGrid(20, 1.0, 0.1, 28);
  for (InterpMode mode : {InterpMode::Exact, InterpMode::Thesis}) {
    KernelInterpolator interp;
    GaussianKernel k = kernelFor(1.0);
    k.sigma = 10.0;  // 10× the spacing
    InterpolatorReport rep;
    ASSERT_NO_THROW(rep = interp.compute(X, k, mode));
    EXPECT_NE(rep.status, SolveStatus::Ok);
    EXPECT_FALSE(interp.ok());
    EXPECT_NE(rep.advice.find("sigma"), std::string::npos) << rep.advice;
    EXPECT_THROW(interp.solve(Weights::Ones(X.rows(), 1)), std::logic_error);
  }
}

TEST(Interpolator, ReportsSizesAndStartsNotComputed) {
  KernelInterpolator interp;
  EXPECT_FALSE(interp.ok());
  const Points X = jitteredGrid(10, 1.0, 0.1, 29);
  const InterpolatorReport rep = interp.compute(X, kernelFor(1.0));
  EXPECT_EQ(rep.status, SolveStatus::Ok);
  EXPECT_TRUE(rep.advice.empty());
  EXPECT_EQ(rep.nonZeros, assembleKernelMatrix(X, kernelFor(1.0)).nonZeros());
  EXPECT_EQ(interp.mode(), InterpMode::Exact);
  EXPECT_EQ(interp.samples().rows(), 100);
}

TEST(Interpolator, CollinearSamplesInExactModeAreReported) {
  Points X(30, 2);
  for (int i = 0; i < 30; ++i) X.row(i) << i, 2.0 * i;
  KernelInterpolator interp;
  const InterpolatorReport rep = interp.compute(X, kernelFor(1.0), InterpMode::Exact);
  EXPECT_EQ(rep.status, SolveStatus::Singular);
  EXPECT_FALSE(rep.advice.empty());
}

TEST(Interpolator, RefinementKeepsTheInterpolantAndShrinksTheResidual) {
  const Points X = jitteredGrid(20, 1.0, 0.3, 31);
  const Weights W = randomWeights(X.rows(), 3, 32);
  for (InterpMode mode : {InterpMode::Exact, InterpMode::Thesis}) {
    KernelInterpolator interp;
    ASSERT_EQ(interp.compute(X, kernelFor(1.0), mode).status, SolveStatus::Ok);
    const KernelCoefficients a = interp.solve(W), b = interp.solve(W, 2);
    const Weights wa = interp.evaluate(a, X), wb = interp.evaluate(b, X);
    EXPECT_LE((wa - wb).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LE((wb - W).cwiseAbs().maxCoeff(), (wa - W).cwiseAbs().maxCoeff() + 1e-15);
  }
}

TEST(Interpolator, RejectsBadInput) {
  Points X = jitteredGrid(6, 1.0, 0.1, 30);
  KernelInterpolator interp;
  GaussianKernel k = kernelFor(1.0);
  k.sigma = -1.0;
  EXPECT_THROW(interp.compute(X, k), std::invalid_argument);
  EXPECT_THROW(interp.compute(Points(0, 2), kernelFor(1.0)), std::invalid_argument);
  ASSERT_TRUE(interp.compute(X, kernelFor(1.0)).status == SolveStatus::Ok);
  EXPECT_THROW(interp.solve(Weights::Ones(X.rows() + 1, 2)), std::invalid_argument);
  Weights W = Weights::Ones(X.rows(), 2);
  W(0, 0) = std::nan("");
  EXPECT_THROW(interp.solve(W), std::invalid_argument);
  const KernelCoefficients coef = interp.solve(Weights::Ones(X.rows(), 2));
  Points P(1, 2);
  P << std::nan(""), 0.0;
  EXPECT_THROW(interp.evaluate(coef, P), std::invalid_argument);
  X(2, 0) = std::nan("");
  EXPECT_THROW(interp.compute(X, kernelFor(1.0)), std::invalid_argument);
}

}  // namespace
}  // namespace kc
