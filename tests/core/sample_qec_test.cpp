// QEC (thesis 4.2–4.6) against a dense KKT solve, and the shared ControlFrame.
#include "kc/core/weights/sample_qec.h"

#include <gtest/gtest.h>

#include "sample_problems.h"

#include <Eigen/Dense>
#include <random>
#include <stdexcept>
#include "random_point.h"

namespace kc {
namespace {

using test::randomControls;

/// Reference: the KKT system [2I Aᵀ; A 0][w; ν] = [2w0; b] of (4.2) in the original coordinates,
/// solved by full-pivoting LU.
Eigen::VectorXd kktReference(const Points& C, const Vec2& x, const Eigen::VectorXd& w0) {
  const Index m = C.rows();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(m + 3, m + 3);
  K.topLeftCorner(m, m) = 2.0 * Eigen::MatrixXd::Identity(m, m);
  for (Index i = 0; i < m; ++i) {
    const Eigen::Vector3d a(C(i, 0), C(i, 1), 1.0);
    K.block(i, m, 1, 3) = a.transpose();
    K.block(m, i, 3, 1) = a;
  }
  Eigen::VectorXd rhs(m + 3);
  rhs << 2.0 * w0, x.x(), x.y(), 1.0;
  return K.fullPivLu().solve(rhs).head(m);
}

TEST(SampleQec, MatchesDenseKktSolveOnRandomProblems) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const int m = 3 + trial % 38;
    // Pixel-like coordinates far from the origin exercise the normalization.
    const Points C = randomControls(rng, m, trial % 2 ? 300.0 : 1.0, trial % 2 ? Vec2(500, 400) : Vec2::Zero());
    const Vec2 x = Vec2(C.colwise().mean()) + 0.5 * (trial % 2 ? 300.0 : 1.0) * test::randomPoint(u, rng);
    const Eigen::VectorXd w0 = Eigen::VectorXd::Random(m);
    const ControlFrame frame(C);
    Eigen::VectorXd w(m);
    sampleQec(frame, frame.normalize(x), {w0.data(), static_cast<std::size_t>(m)}, {w.data(), static_cast<std::size_t>(m)});
    const Eigen::VectorXd ref = kktReference(C, x, w0);
    EXPECT_LE((w - ref).lpNorm<Eigen::Infinity>(), 1e-10 * (1.0 + ref.lpNorm<Eigen::Infinity>())) << trial;
    EXPECT_NEAR(w.sum(), 1.0, 1e-13);
    const double scale = trial % 2 ? 300.0 : 1.0;
    EXPECT_LE((C.transpose() * w - x).lpNorm<Eigen::Infinity>(), 1e-12 * scale * (1.0 + w.lpNorm<1>()));
    // The closed form (4.4)–(4.6) is the KKT solution: w − w0 lies in the row space of A.
  }
}

TEST(SampleQec, InPlaceAndMultipliersAgree) {
  std::mt19937 rng(2);
  const Points C = randomControls(rng, 9, 1.0, Vec2::Zero());
  const ControlFrame frame(C);
  const Vec2 xh = frame.normalize(Vec2(0.1, 0.2));
  Eigen::VectorXd w0 = Eigen::VectorXd::Random(9), w(9);
  const Eigen::Vector3d lambda = sampleQec(frame, xh, {w0.data(), 9}, {w.data(), 9});
  EXPECT_EQ(lambda, qecMultipliers(frame, xh, {w0.data(), 9}));
  sampleQec(frame, xh, {w0.data(), 9}, {w0.data(), 9});  // aliasing allowed
  EXPECT_EQ(w, w0);
}

TEST(SampleQec, EdgeWeightsAreLinear) {
  Points C(3, 2);
  C << 0, 0, 4, 0, 0, 3;
  Eigen::VectorXd w(3);
  edgeWeights(C, 1, 2, Vec2(1, 2.25), {w.data(), 3});
  EXPECT_DOUBLE_EQ(w(0), 0.0);
  EXPECT_DOUBLE_EQ(w(1), 0.25);
  EXPECT_DOUBLE_EQ(w(2), 0.75);
}

TEST(ControlFrame, RejectsDegenerateControls) {
  Points two(2, 2);
  two << 0, 0, 1, 1;
  EXPECT_THROW(ControlFrame{two}, std::invalid_argument);
  Points line(4, 2);
  line << 0, 0, 1, 1, 2, 2, 5, 5;
  EXPECT_THROW(ControlFrame{line}, std::invalid_argument);
  Points nan(3, 2);
  nan << 0, 0, 1, std::nan(""), 0, 1;
  EXPECT_THROW(ControlFrame{nan}, std::invalid_argument);
}

TEST(ControlFrame, HullTests) {
  Points C(4, 2);
  C << 0, 0, 10, 0, 10, 10, 0, 10;
  const ControlFrame frame(C);
  EXPECT_LT(frame.hullExcess(frame.normalize(Vec2(5, 5))), 0.0);
  EXPECT_NEAR(frame.hullExcess(frame.normalize(Vec2(10, 5))), 0.0, 1e-15);
  EXPECT_GT(frame.hullExcess(frame.normalize(Vec2(12, 5))), 0.0);
  EXPECT_DOUBLE_EQ(frame.hullShrink(frame.normalize(Vec2(15, 5))), 0.5);  // (15,5) → (10,5) from (5,5)
  EXPECT_DOUBLE_EQ(frame.hullShrink(frame.normalize(Vec2(3, 4))), 1.0);
}

}  // namespace
}  // namespace kc
