#pragma once
/// Poses and linear blend skinning (thesis 3.5): f(x) = Σ_i w_i(x) T_i x (3.37).

#include <vector>

#include "kc/core/types.h"

namespace kc {

/// One control point's transform: rotation by `rotate` radians (counter-clockwise on screen, i.e.
/// in x-right/y-down pixel axes) about its rest position, then translation by `translate`.
struct HandlePose {
  Vec2 translate = Vec2::Zero();
  double rotate = 0.0;
};

/// One HandlePose per control point. An empty pose, or all-zero handles, is the rest pose.
using Pose = std::vector<HandlePose>;

/// The rest pose for m control points.
inline Pose restPose(Index m) { return Pose(static_cast<std::size_t>(m)); }

/// True when every handle has zero translation and rotation (an empty pose is the rest pose).
bool isRestPose(const Pose& pose);

/// Throws std::invalid_argument, naming the handle, when the pose is unusable for m control
/// points: a non-empty pose whose size is not m, or a non-finite translation or rotation.
void validatePose(const Pose& pose, Index m);

/// The pose that moves control points C (m×2) to positions P (m×2) without rotation:
/// t_i = p_i − c_i, θ_i = 0 (the "positions" form of a pose file). Throws on shape mismatch.
Pose poseFromPositions(const Points& C, const Points& P);

/// Rotation by θ counter-clockwise on screen in x-right/y-down axes: [[cos θ, sin θ], [−sin θ, cos θ]].
Eigen::Matrix2d screenRotation(double theta);

/// T_i as a 2×3 affine map for control point c: x ↦ R(θ)(x − c) + c + t.
Affine2 handleTransform(const Vec2& c, const HandlePose& pose);

/// All m handle transforms T_i; an empty pose gives identities. Validates the pose.
std::vector<Affine2> handleTransforms(const Points& C, const Pose& pose);

/// Deformed control point positions (m×2): c_i + t_i.
Points posedControls(const Points& C, const Pose& pose);

/// Dense linear blend skinning (3.37): row p of the result is Σ_i W(p,i) T_i [x_p; 1] for
/// points X (#P×2) with weights W (#P×m) and transforms T (m). Parallel over rows.
Points blendPoints(const Weights& W, const Points& X, const std::vector<Affine2>& T);

/// Convenience: blendPoints(W, X, handleTransforms(C, pose)).
Points deformPoints(const Weights& W, const Points& X, const Points& C, const Pose& pose);

}  // namespace kc
