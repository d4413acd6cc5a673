// The local projection of screened targets (heat_diffusion.h, InitOptions::locality).
#include "local_projection.h"

#include <Eigen/Dense>
#include <algorithm>

namespace kc::detail {

/// Moves a screened target row w0 (positive, sum 1) to reproduce x while staying close to it in
/// the metric Σ (w_i − w0_i)² / w0_i: min that s.t. Σ w_i c_i = x, Σ w_i = 1, w ≥ 0. Corrections
/// are proportional to the targets, so controls with negligible targets stay negligible (the
/// row stays local) and they are recruited only as far as reproduction needs them. Solved in the
/// 3-variable dual (w(λ) = max(0, w0 + w0 ∘ Aᵀλ), damped Newton). Returns false when x is not
/// reproducible with w ≥ 0 (outside the controls' hull) or Newton stalls; w0 is then left as is.
bool projectTargetsLocally(const Points& C, const Vec2& x, Eigen::Ref<Eigen::RowVectorXd> w0) {
  const Index m = C.rows();
  // Centred, scaled coordinates keep the 3×3 systems well conditioned.
  const Vec2 c0 = C.colwise().mean().transpose();
  const double scale = std::max(1e-300, (C.rowwise() - c0.transpose()).cwiseAbs().maxCoeff());
  Eigen::Matrix<double, 3, Eigen::Dynamic> A(3, m);
  for (Index i = 0; i < m; ++i) A.col(i) << (C(i, 0) - c0.x()) / scale, (C(i, 1) - c0.y()) / scale, 1.0;
  const Eigen::Vector3d b((x.x() - c0.x()) / scale, (x.y() - c0.y()) / scale, 1.0);
  // Metric weights: the targets, floored at 1e-8 of the largest so the dual stays well posed
  // where reproduction has to recruit controls whose screened targets underflowed.
  const Eigen::VectorXd d = w0.transpose().cwiseMax(1e-8 * w0.maxCoeff());
  auto weights = [&](const Eigen::Vector3d& lambda) {
    return Eigen::VectorXd((d.array() * (1.0 + (A.transpose() * lambda).array())).cwiseMax(0.0));
  };
  auto dual = [&](const Eigen::Vector3d& lambda, const Eigen::VectorXd& w) {  // convex, C¹
    return 0.5 * (w.array().square() / d.array()).sum() - b.dot(lambda) - 0.5 * d.sum();
  };
  Eigen::Vector3d lambda = Eigen::Vector3d::Zero();
  Eigen::VectorXd w = weights(lambda);
  for (int it = 0; it < 200; ++it) {
    const Eigen::Vector3d g = A * w - b;
    if (g.cwiseAbs().maxCoeff() <= 1e-11) {  // normalized units: ~1e-11 of the cage size
      w0 = w.transpose();
      return true;
    }
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    for (Index i = 0; i < m; ++i)
      if (w(i) > 0.0) H.noalias() += d(i) * A.col(i) * A.col(i).transpose();
    H.diagonal().array() += 1e-14 * (H.trace() + 1e-300);
    const Eigen::Vector3d step = -H.ldlt().solve(g);
    if (!step.allFinite()) return false;
    const double f0 = dual(lambda, w);
    double t = 1.0;
    Eigen::VectorXd wt;
    for (int k = 0; k < 60; ++k, t *= 0.5) {  // Armijo backtracking on the dual objective
      wt = weights(lambda + t * step);
      if (dual(lambda + t * step, wt) <= f0 + 1e-4 * t * g.dot(step)) break;
    }
    lambda += t * step;
    w = wt;
    if (!lambda.allFinite() || lambda.norm() > 1e12) return false;  // infeasible: λ diverges
  }
  return false;
}

}  // namespace kc::detail
