#pragma once
// Private to kc::core's initial weights (heat_diffusion.cpp).

#include "kc/core/types.h"

namespace kc::detail {

/// Moves a screened target row w0 (length m, positive, sum 1) to reproduce x with the controls C
/// (m×2): min Σ (w_i − w0_i)² / w0_i s.t. Σ w_i c_i = x, Σ w_i = 1, w ≥ 0. False (w0 untouched)
/// when x is outside the controls' hull or Newton stalls. See local_projection.cpp.
bool projectTargetsLocally(const Points& C, const Vec2& x, Eigen::Ref<Eigen::RowVectorXd> w0);

}  // namespace kc::detail
