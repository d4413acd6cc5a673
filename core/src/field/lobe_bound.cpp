// The lobe bound: the field's weights projected onto w ≥ ℓ(x) where they fall below it (lobe_bound.h).
#include "kc/core/field/lobe_bound.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "kc/core/parallel.h"
#include "kc/core/weights/optimizer.h"
#include "kc/core/weights/sample_qp.h"

namespace kc {
namespace {

/// Rows of W with a weight below −depth: the only ones the bound can change (ℓ ≤ −depth).
std::vector<Index> candidateRows(const Weights& W, double depth, const std::vector<Index>* rows) {
  std::vector<Index> out;
  const Index n = rows ? static_cast<Index>(rows->size()) : W.rows();
  for (Index k = 0; k < n; ++k) {
    const Index i = rows ? (*rows)[static_cast<std::size_t>(k)] : k;
    if (W.row(i).minCoeff() < -depth) out.push_back(i);
  }
  return out;
}

}  // namespace

LobeBound::LobeBound(const Cage& cage, double depth, double fade, double allowance)
    : m_cage(cage), m_queries(m_cage), m_depth(depth), m_fade(fade), m_allowance(allowance) {
  if (!(depth >= 0.0) || !std::isfinite(depth)) throw std::invalid_argument("lobe bound: the depth must be a finite number >= 0");
  if (!(fade > 0.0) || !std::isfinite(fade)) throw std::invalid_argument("lobe bound: the fade length must be a positive number");
  if (!(allowance >= 0.0) || !std::isfinite(allowance))
    throw std::invalid_argument("lobe bound: the allowance must be a finite number >= 0");
  if (!hasInterior(m_cage)) throw std::invalid_argument("lobe bound: the cage has no interior");
  m_frame = ControlFrame(m_cage.C);
}

double LobeBound::bound(const Vec2& x) const {
  if (m_queries.inside(x)) return -m_depth;
  return -m_depth - m_queries.distance(x) / m_fade;
}

bool LobeBound::projectRow(const Vec2& x, double l, std::span<double> w, std::vector<double>& target,
                           std::vector<double>& a) const {
  if (!(*std::min_element(w.begin(), w.end()) < l)) return false;
  target.assign(w.begin(), w.end());
  a.clear();
  if (m_allowance > 0.0)
    for (double v : target) a.push_back(allowanceOf(v, m_allowance));
  sampleQpAbove(m_frame, m_frame.normalize(x), target, l, a, w);
  return true;
}

std::vector<double> LobeBound::bounds(const Points& P) const {
  std::vector<double> l(static_cast<std::size_t>(P.rows()));
  parallelForRange(P.rows(), 256, [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) l[static_cast<std::size_t>(i)] = bound(P.row(i).transpose());
  });
  return l;
}

std::vector<Index> LobeBound::apply(const Points& P, Weights& W) const { return apply(P, W, {}); }

std::vector<Index> LobeBound::apply(const Points& P, Weights& W, const std::vector<Index>& rows) const {
  checkShapes(P, W);
  const std::vector<Index> candidates = candidateRows(W, m_depth, rows.empty() ? nullptr : &rows);
  std::vector<char> changed(candidates.size(), 0);
  parallelForRange(static_cast<Index>(candidates.size()), 64, [&](Index begin, Index end) {
    std::vector<double> target, a;
    for (Index k = begin; k < end; ++k) {
      const Index i = candidates[static_cast<std::size_t>(k)];
      const Vec2 x = P.row(i).transpose();
      changed[static_cast<std::size_t>(k)] =
          projectRow(x, bound(x), std::span<double>(W.row(i).data(), static_cast<std::size_t>(W.cols())), target, a);
    }
  });
  std::vector<Index> out;
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (changed[k]) out.push_back(candidates[k]);
  return out;
}

void LobeBound::project(const Points& P, std::span<const double> bounds, const std::vector<Index>& rows, Weights& W) const {
  checkShapes(P, W);
  if (bounds.size() != static_cast<std::size_t>(P.rows()))
    throw std::invalid_argument("lobe bound: one bound per point is needed");
  parallelForRange(static_cast<Index>(rows.size()), 64, [&](Index begin, Index end) {
    std::vector<double> target, a;
    for (Index k = begin; k < end; ++k) {
      const Index i = rows[static_cast<std::size_t>(k)];
      projectRow(P.row(i).transpose(), bounds[static_cast<std::size_t>(i)],
                 std::span<double>(W.row(i).data(), static_cast<std::size_t>(W.cols())), target, a);
    }
  });
}

void LobeBound::checkShapes(const Points& P, const Weights& W) const {
  if (P.rows() != W.rows() || W.cols() != m_cage.size())
    throw std::invalid_argument("lobe bound: the weights must have one row per point and one column per control");
}

void LobeBound::applyGradients(const Points& P, const Weights& W, Weights& dWdx, Weights& dWdy) const {
  const Index m = m_cage.size();
  checkShapes(P, W);
  if (dWdx.rows() != W.rows() || dWdy.rows() != W.rows() || dWdx.cols() != m || dWdy.cols() != m)
    throw std::invalid_argument("lobe bound: the gradients must have the weights' shape");
  const std::vector<Index> candidates = candidateRows(W, m_depth, nullptr);
  const double invScale = (m_frame.normalize(Vec2(1.0, 0.0)) - m_frame.normalize(Vec2(0.0, 0.0))).x();  // ∂x̂/∂x
  const double cap = kAllowanceCap * m_allowance;
  parallelForRange(static_cast<Index>(candidates.size()), 64, [&](Index begin, Index end) {
    std::vector<double> target, a;
    Eigen::RowVectorXd v(m);
    for (Index k = begin; k < end; ++k) {
      const Index i = candidates[static_cast<std::size_t>(k)];
      const Vec2 x = P.row(i).transpose();
      v = W.row(i);
      const double l = bound(x);
      if (!projectRow(x, l, std::span<double>(v.data(), static_cast<std::size_t>(m)), target, a)) continue;
      // ∂ℓ: 0 inside; outside −∇d/fade, by central differences (d is smooth off the cage's medial
      // axis: its gradient is the unit vector from the nearest cage point).
      Vec2 dl = Vec2::Zero();
      if (!m_queries.inside(x)) {
        const double e = 1e-4 * m_fade;
        dl.x() = (bound(x + Vec2(e, 0.0)) - bound(x - Vec2(e, 0.0))) / (2.0 * e);
        dl.y() = (bound(x + Vec2(0.0, e)) - bound(x - Vec2(0.0, e))) / (2.0 * e);
      }
      // Active set J (at the bound within rounding) and free set F; M = A_F D_F A_Fᵀ, and the
      // multipliers λ = M⁻¹ A_F Δ_F of the projection's step Δ = v − w.
      const double tol = 1e-12 * (1.0 + std::abs(l));
      auto column = [&](Index j) { return Eigen::Vector3d(m_frame.cx()[j], m_frame.cy()[j], 1.0); };
      auto metric = [&](Index j) { return a.empty() ? 1.0 : a[static_cast<std::size_t>(j)]; };
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      Eigen::Vector3d aJ = Eigen::Vector3d::Zero(), step = Eigen::Vector3d::Zero();
      std::vector<char> active(static_cast<std::size_t>(m), 0);
      for (Index j = 0; j < m; ++j) {
        if (v(j) <= l + tol) {
          active[static_cast<std::size_t>(j)] = 1;
          aJ += column(j);
        } else {
          M.noalias() += metric(j) * column(j) * column(j).transpose();
          step += column(j) * (v(j) - W(i, j));
        }
      }
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(M);
      const Eigen::Vector3d lambda = ldlt.solve(step);
      for (int axis = 0; axis < 2; ++axis) {
        Weights& G = axis == 0 ? dWdx : dWdy;
        Eigen::Vector3d rhs(axis == 0 ? invScale : 0.0, axis == 1 ? invScale : 0.0, 0.0);
        rhs -= aJ * dl(axis);
        std::vector<double> dA(static_cast<std::size_t>(m), 0.0);  // ∂a_j
        for (Index j = 0; j < m; ++j) {
          if (active[static_cast<std::size_t>(j)]) continue;
          const double wj = W(i, j);
          if (!a.empty() && wj > 0.0 && wj < cap) dA[static_cast<std::size_t>(j)] = G(i, j);
          rhs -= column(j) * (G(i, j) + dA[static_cast<std::size_t>(j)] * column(j).dot(lambda));
        }
        const Eigen::Vector3d dlambda = ldlt.solve(rhs);
        for (Index j = 0; j < m; ++j)
          G(i, j) = active[static_cast<std::size_t>(j)]
                        ? dl(axis)
                        : G(i, j) + dA[static_cast<std::size_t>(j)] * column(j).dot(lambda) + metric(j) * column(j).dot(dlambda);
      }
    }
  });
}

}  // namespace kc
