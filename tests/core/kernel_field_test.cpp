#include "kc/core/field/kernel_field.h"

#include <gtest/gtest.h>

#include <vector>

#include "point_problems.h"

namespace kc {
namespace {

using test::kernelFor;
using test::randomWeights;

Points randomPoints(int count, double lo, double hi, unsigned seed) { return test::randomPointsIn(count, lo, hi, seed); }

struct Bound {
  Points X;
  Weights W;
  KernelField field;
  KernelInterpolator interp;  // the interpolator path the field replaces
  KernelCoefficients coef;
};

Bound bindBoth(InterpMode mode) {
  Bound b;
  b.X = test::jitteredGrid(18, 3.0, 0.2, 5);
  b.W = randomWeights(b.X.rows(), 4, 6);
  EXPECT_EQ(b.field.compute(b.X, kernelFor(3.0), mode).status, SolveStatus::Ok);
  b.field.update(b.W);
  EXPECT_EQ(b.interp.compute(b.X, kernelFor(3.0), mode).status, SolveStatus::Ok);
  b.coef = b.interp.solve(b.W);
  return b;
}

class KernelFieldModes : public ::testing::TestWithParam<InterpMode> {};

TEST_P(KernelFieldModes, SameBitsAsTheInterpolatorPath) {
  const Bound b = bindBoth(GetParam());
  ASSERT_TRUE(b.field.ready());
  const Points P = randomPoints(300, -10.0, 60.0, 7);
  EXPECT_TRUE(b.field.weightsAt(P) == b.interp.evaluate(b.coef, P));  // bit for bit
  Weights gx, gy, rx, ry;
  b.field.gradientsAt(P, gx, gy);
  b.interp.evaluateGradient(b.coef, P, rx, ry);
  EXPECT_TRUE(gx == rx && gy == ry);
  EXPECT_TRUE(b.field.kernelCoefficients().U == b.coef.U);
  EXPECT_TRUE(b.field.kernelCoefficients().B == b.coef.B);
}

TEST_P(KernelFieldModes, OperatorTimesCoefficientsIsTheField) {
  const Bound b = bindBoth(GetParam());
  const Points P = randomPoints(300, -10.0, 60.0, 8);
  const SparseRowMatrix E = b.field.evaluationOperator(P);
  ASSERT_EQ(E.rows(), P.rows());
  ASSERT_EQ(E.cols(), b.field.nodes());
  const Weights viaE = E * b.field.coefficients();
  const Weights direct = b.field.weightsAt(P);
  EXPECT_LE((viaE - direct).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + direct.cwiseAbs().maxCoeff()));
  Weights applied(P.rows(), b.field.controls());
  b.field.apply(E, {}, applied);
  EXPECT_LE((applied - direct).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + direct.cwiseAbs().maxCoeff()));
}

TEST_P(KernelFieldModes, GradientOperatorsMatchFiniteDifferences) {
  const Bound b = bindBoth(GetParam());
  const Points P = randomPoints(60, 5.0, 45.0, 9);
  SparseRowMatrix Ex, Ey;
  b.field.gradientOperators(P, Ex, Ey);
  const RowMatrix C = b.field.coefficients();
  const Weights gx = Ex * C, gy = Ey * C;
  const double h = 1e-5;
  Points Px = P, Py = P, Pxm = P, Pym = P;
  Px.col(0).array() += h;
  Pxm.col(0).array() -= h;
  Py.col(1).array() += h;
  Pym.col(1).array() -= h;
  const Weights fx = (b.field.weightsAt(Px) - b.field.weightsAt(Pxm)) / (2 * h);
  const Weights fy = (b.field.weightsAt(Py) - b.field.weightsAt(Pym)) / (2 * h);
  const double scale = fx.cwiseAbs().maxCoeff() + fy.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 1e-3);  // the weights vary: the comparison means something
  EXPECT_LE((gx - fx).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_LE((gy - fy).cwiseAbs().maxCoeff(), 1e-6 * scale);
}

TEST_P(KernelFieldModes, ColumnUpdateEqualsAFullSolve) {
  Bound b = bindBoth(GetParam());
  Weights W2 = b.W;
  W2.col(2) = randomWeights(b.X.rows(), 1, 10);
  const std::vector<Index> cols = {2};
  b.field.update(W2, cols);
  KernelField full;
  ASSERT_EQ(full.compute(b.X, kernelFor(3.0), GetParam()).status, SolveStatus::Ok);
  full.update(W2);
  const Points P = randomPoints(200, 0.0, 50.0, 11);
  const Weights a = b.field.weightsAt(P), f = full.weightsAt(P);
  EXPECT_LE((a - f).cwiseAbs().maxCoeff(), 1e-9);
  // The untouched columns keep their coefficients exactly.
  EXPECT_TRUE(b.field.kernelCoefficients().U.col(0) == b.coef.U.col(0));
}

TEST_P(KernelFieldModes, ReleasedFactorizationStillEvaluatesAndFactorsAgainOnUpdate) {
  Bound b = bindBoth(GetParam());
  const Points P = randomPoints(100, 0.0, 50.0, 12);
  const Weights before = b.field.weightsAt(P);
  b.field.releaseFactorization();
  EXPECT_FALSE(b.field.factorized());
  ASSERT_TRUE(b.field.ready());
  EXPECT_TRUE(b.field.weightsAt(P) == before);
  b.field.update(b.W);
  EXPECT_TRUE(b.field.factorized());
  EXPECT_TRUE(b.field.kernelCoefficients().U == b.coef.U) << "the same factor again, the same coefficients";
  EXPECT_TRUE(b.field.kernelCoefficients().B == b.coef.B);
}

INSTANTIATE_TEST_SUITE_P(Modes, KernelFieldModes, ::testing::Values(InterpMode::Exact, InterpMode::Thesis),
                         [](const auto& info) { return info.param == InterpMode::Exact ? "Exact" : "Thesis"; });

TEST(KernelField, DefinedOnThePlane) {
  const Bound b = bindBoth(InterpMode::Exact);
  EXPECT_EQ(b.field.domain(), FieldDomain::Plane);
  EXPECT_TRUE(b.field.contains(Vec2(-1e6, 1e6)));
}

TEST(KernelField, UpdateWithoutComputeIsAnError) {
  KernelField f;
  EXPECT_FALSE(f.ready());
  EXPECT_THROW(f.update(Weights::Ones(3, 2)), std::logic_error);
}

}  // namespace
}  // namespace kc
