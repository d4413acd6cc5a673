#include "kc/core/deform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace kc {
namespace {

/// Bilinear (quad) coordinates on the axis-aligned rectangle [x0,x1]×[y0,y1], corners ordered
/// (x0,y0), (x1,y0), (x1,y1), (x0,y1): partition of unity and linear reproduction everywhere.
Weights quadWeights(const Points& X, double x0, double y0, double x1, double y1) {
  Weights W(X.rows(), 4);
  for (Index p = 0; p < X.rows(); ++p) {
    const double u = (X(p, 0) - x0) / (x1 - x0), v = (X(p, 1) - y0) / (y1 - y0);
    W.row(p) << (1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v;
  }
  return W;
}

struct Fixture {
  Points C{{10, 20}, {110, 20}, {110, 80}, {10, 80}};
  Points X;
  Weights W;
  Fixture() {
    X.resize(50, 2);
    for (Index p = 0; p < X.rows(); ++p) X.row(p) << 5 + 2.3 * p, 15 + std::fmod(7.1 * p, 70.0);
    W = quadWeights(X, 10, 20, 110, 80);
  }
};

TEST(Deform, ScreenRotationIsCounterClockwiseOnScreen) {
  // With y pointing down, a quarter turn counter-clockwise on screen takes "right" to "up" (−y).
  const Vec2 c(3, 4);
  HandlePose h;
  h.rotate = std::numbers::pi / 2;
  const Affine2 T = handleTransform(c, h);
  const Vec2 q = T.leftCols<2>() * (c + Vec2(1, 0)) + T.col(2);
  EXPECT_NEAR((q - (c + Vec2(0, -1))).norm(), 0.0, 1e-12);
  const Vec2 qc = T.leftCols<2>() * c + T.col(2);
  EXPECT_NEAR((qc - c).norm(), 0.0, 1e-12);  // rotation about the rest position
}

TEST(Deform, RestPoseIsIdentity) {
  Fixture f;
  EXPECT_TRUE(isRestPose({}));
  EXPECT_TRUE(isRestPose(restPose(4)));
  for (const Pose& pose : {Pose{}, restPose(4)}) {
    const Points F = deformPoints(f.W, f.X, f.C, pose);
    EXPECT_LT((F - f.X).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(Deform, CommonTranslationMovesEverything) {
  Fixture f;
  Pose pose = restPose(4);
  for (auto& h : pose) h.translate = Vec2(7.5, -3.25);
  const Points F = deformPoints(f.W, f.X, f.C, pose);
  for (Index p = 0; p < f.X.rows(); ++p) {
    EXPECT_NEAR(F(p, 0), f.X(p, 0) + 7.5, 1e-12);
    EXPECT_NEAR(F(p, 1), f.X(p, 1) - 3.25, 1e-12);
  }
}

TEST(Deform, CommonRigidRotationIsReproducedByPartitionOfUnity) {
  // Every handle rotates by θ and moves its control point along the rotation about o:
  // T_i x = R(x − o) + o for all i.
  Fixture f;
  const double theta = 0.4;
  const Vec2 o(40, 50);
  const Eigen::Matrix2d R = screenRotation(theta);
  Pose pose = restPose(4);
  for (Index i = 0; i < 4; ++i) {
    const Vec2 c = f.C.row(i).transpose();
    pose[std::size_t(i)] = {R * (c - o) + o - c, theta};
  }
  const Points F = deformPoints(f.W, f.X, f.C, pose);
  for (Index p = 0; p < f.X.rows(); ++p) {
    const Vec2 expect = R * (f.X.row(p).transpose() - o) + o;
    EXPECT_NEAR((F.row(p).transpose() - expect).norm(), 0.0, 1e-10);
  }
}

TEST(Deform, ControlsMovedByAnAffineMapGiveThatMap) {
  // Linear reproduction (Σ w_i c_i = x) + partition of unity ⇒ f(x) = A x + b exactly.
  Fixture f;
  Eigen::Matrix2d A;
  A << 1.2, 0.3, -0.2, 0.9;
  const Vec2 b(5, -7);
  Points P(4, 2);
  for (Index i = 0; i < 4; ++i) P.row(i) = (A * f.C.row(i).transpose() + b).transpose();
  const Pose pose = poseFromPositions(f.C, P);
  EXPECT_LT((posedControls(f.C, pose) - P).cwiseAbs().maxCoeff(), 1e-12);
  const Points F = deformPoints(f.W, f.X, f.C, pose);
  for (Index p = 0; p < f.X.rows(); ++p)
    EXPECT_NEAR((F.row(p).transpose() - (A * f.X.row(p).transpose() + b)).norm(), 0.0, 1e-10);
}

TEST(Deform, RejectsBadPoses) {
  Fixture f;
  EXPECT_THROW(validatePose(restPose(3), 4), std::invalid_argument);
  Pose nan = restPose(4);
  nan[2].translate.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(validatePose(nan, 4), std::invalid_argument);
  Pose inf = restPose(4);
  inf[1].rotate = std::numeric_limits<double>::infinity();
  EXPECT_THROW(deformPoints(f.W, f.X, f.C, inf), std::invalid_argument);
  EXPECT_THROW(poseFromPositions(f.C, Points(3, 2)), std::invalid_argument);
  EXPECT_THROW(blendPoints(Weights(3, 4), f.X, handleTransforms(f.C, {})), std::invalid_argument);
  try {
    validatePose(restPose(5), 4);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("5 handles"), std::string::npos);
  }
}

}  // namespace
}  // namespace kc
