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

/// T_i as a 2×3 affine map for control point c: x ↦ R(θ)(x − c) + c + t.
Affine2 handleTransform(const Vec2& c, const HandlePose& pose);

/// Deformed control point positions (m×2): c_i + t_i.
Points posedControls(const Points& C, const Pose& pose);

}  // namespace kc
