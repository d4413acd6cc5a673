#include "kc/core/deform.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "kc/core/parallel.h"

namespace kc {

bool isRestPose(const Pose& pose) {
  for (const HandlePose& h : pose)
    if (h.translate.x() != 0.0 || h.translate.y() != 0.0 || h.rotate != 0.0) return false;
  return true;
}

void validatePose(const Pose& pose, Index m) {
  if (!pose.empty() && static_cast<Index>(pose.size()) != m)
    throw std::invalid_argument("pose has " + std::to_string(pose.size()) + " handles but the cage has " +
                                std::to_string(m) + " control points");
  for (std::size_t i = 0; i < pose.size(); ++i) {
    const HandlePose& h = pose[i];
    if (!std::isfinite(h.translate.x()) || !std::isfinite(h.translate.y()))
      throw std::invalid_argument("pose handle " + std::to_string(i) + " has a non-finite translation");
    if (!std::isfinite(h.rotate))
      throw std::invalid_argument("pose handle " + std::to_string(i) + " has a non-finite rotation");
  }
}

Pose poseFromPositions(const Points& C, const Points& P) {
  if (P.rows() != C.rows())
    throw std::invalid_argument("pose has " + std::to_string(P.rows()) + " positions but the cage has " +
                                std::to_string(C.rows()) + " control points");
  Pose pose(static_cast<std::size_t>(C.rows()));
  for (Index i = 0; i < C.rows(); ++i) pose[static_cast<std::size_t>(i)].translate = (P.row(i) - C.row(i)).transpose();
  validatePose(pose, C.rows());
  return pose;
}

Eigen::Matrix2d screenRotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d R;
  R << c, s, -s, c;
  return R;
}

Affine2 handleTransform(const Vec2& c, const HandlePose& pose) {
  const Eigen::Matrix2d R = screenRotation(pose.rotate);
  Affine2 T;
  T.leftCols<2>() = R;
  T.col(2) = c - R * c + pose.translate;
  return T;
}

std::vector<Affine2> handleTransforms(const Points& C, const Pose& pose) {
  validatePose(pose, C.rows());
  std::vector<Affine2> T(static_cast<std::size_t>(C.rows()));
  for (Index i = 0; i < C.rows(); ++i) {
    const HandlePose h = pose.empty() ? HandlePose{} : pose[static_cast<std::size_t>(i)];
    T[static_cast<std::size_t>(i)] = handleTransform(C.row(i).transpose(), h);
  }
  return T;
}

Points posedControls(const Points& C, const Pose& pose) {
  validatePose(pose, C.rows());
  Points P = C;
  for (std::size_t i = 0; i < pose.size(); ++i) P.row(static_cast<Index>(i)) += pose[i].translate.transpose();
  return P;
}

Points blendPoints(const Weights& W, const Points& X, const std::vector<Affine2>& T) {
  const Index m = static_cast<Index>(T.size());
  if (W.rows() != X.rows() || W.cols() != m)
    throw std::invalid_argument("blendPoints: W is " + std::to_string(W.rows()) + "x" + std::to_string(W.cols()) +
                                " but expected " + std::to_string(X.rows()) + "x" + std::to_string(m));
  Points F(X.rows(), 2);
  parallelFor(X.rows(), [&](Index p) {
    Affine2 A = Affine2::Zero();  // T(x) = Σ_i w_i T_i (3.38)
    for (Index i = 0; i < m; ++i) A += W(p, i) * T[static_cast<std::size_t>(i)];
    F.row(p) = (A.leftCols<2>() * X.row(p).transpose() + A.col(2)).transpose();
  }, 1024);
  return F;
}

Points deformPoints(const Weights& W, const Points& X, const Points& C, const Pose& pose) {
  return blendPoints(W, X, handleTransforms(C, pose));
}

}  // namespace kc
