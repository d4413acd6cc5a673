#include "kc/core/exterior_relax.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace kc {
namespace {

using Mat2 = Eigen::Matrix2d;

/// One triangle of a vertex v's star, v's position p free: J(p) = [a − p, b − p] · D⁻¹ with D the
/// rest edges [A − V, B − V]; weight = rest area.
struct StarTriangle {
  Vec2 a, b;
  Mat2 restInverse;
  double weight = 0.0;

  Mat2 jacobian(const Vec2& p) const {
    Mat2 d;
    d.col(0) = a - p;
    d.col(1) = b - p;
    return d * restInverse;
  }
};

/// A sweep that lowers the energy by less than this fraction ends the relaxation. (On the bundled
/// stick figure's pose the smallest det J rises from 4e-5 to 0.19 by then; further sweeps change
/// the picture by less than a pixel.)
constexpr double kSettled = 5e-4;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Symmetric Dirichlet energy ‖J‖²(1 + 1/det²) (the 2-D form of ‖J‖² + ‖J⁻¹‖²); ∞ when det ≤ 0.
double energyOf(const Mat2& J) {
  const double d = J.determinant();
  if (!(d > 0.0)) return kInfinity;
  const double s = J.squaredNorm();
  return s + s / (d * d);
}

class Star {
 public:
  std::vector<StarTriangle> tris;

  double energy(const Vec2& p) const {
    double e = 0.0;
    for (const StarTriangle& t : tris) {
      const double f = energyOf(t.jacobian(p));
      if (!std::isfinite(f)) return kInfinity;
      e += t.weight * f;
    }
    return e;
  }
  double minJacobian(const Vec2& p) const {
    double m = kInfinity;
    for (const StarTriangle& t : tris) m = std::min(m, t.jacobian(p).determinant());
    return m;
  }
  /// ∇_p E: J = C − p gᵀ with gᵀ = [1 1] D⁻¹, so ∂‖J‖²/∂p = −2 J g and ∂det/∂p = (−g₀J₁₁ + g₁J₁₀, −g₁J₀₀ + g₀J₀₁).
  Vec2 gradient(const Vec2& p) const {
    Vec2 grad = Vec2::Zero();
    for (const StarTriangle& t : tris) {
      const Mat2 J = t.jacobian(p);
      const Vec2 g = t.restInverse.transpose() * Vec2(1.0, 1.0);
      const double d = J.determinant(), s = J.squaredNorm();
      const Vec2 ds = -2.0 * (J * g);
      const Vec2 dd(-g(0) * J(1, 1) + g(1) * J(1, 0), -g(1) * J(0, 0) + g(0) * J(0, 1));
      grad += t.weight * (ds * (1.0 + 1.0 / (d * d)) - (2.0 * s / (d * d * d)) * dd);
    }
    return grad;
  }
  /// The shortest star edge from p (steps are kept below half of it).
  double reach(const Vec2& p) const {
    double r = kInfinity;
    for (const StarTriangle& t : tris) r = std::min({r, (t.a - p).norm(), (t.b - p).norm()});
    return r;
  }
};

}  // namespace

ExteriorRelaxReport relaxExteriorRegion(const Points& restX, Points& P, const Triangles& triangles, Index nt,
                                        const ExteriorRepairTopology& topology, const std::vector<int>& region, int sweeps) {
  ExteriorRelaxReport rep;
  const auto tri = [&](Index t) -> const std::array<int, 3>& { return t < nt ? triangles[std::size_t(t)] : topology.ghosts[std::size_t(t - nt)]; };
  // The region's stars' triangles, each once (for the report).
  std::vector<Index> touched;
  {
    std::vector<std::uint8_t> seen(std::size_t(nt) + topology.ghosts.size(), 0);
    for (int v : region)
      for (Index k = topology.start[std::size_t(v)]; k < topology.start[std::size_t(v) + 1]; ++k)
        if (const Index t = topology.around[std::size_t(k)]; !seen[std::size_t(t)]) {
          seen[std::size_t(t)] = 1;
          touched.push_back(t);
        }
  }
  const auto totals = [&](double& energy, double& minJ) {
    energy = 0.0;
    minJ = kInfinity;
    for (Index t : touched) {
      const auto& [i, j, k] = tri(t);
      Mat2 dr, dd;
      dr << restX(j, 0) - restX(i, 0), restX(k, 0) - restX(i, 0), restX(j, 1) - restX(i, 1), restX(k, 1) - restX(i, 1);
      dd << P(j, 0) - P(i, 0), P(k, 0) - P(i, 0), P(j, 1) - P(i, 1), P(k, 1) - P(i, 1);
      const Mat2 J = dd * dr.inverse();
      energy += 0.5 * std::abs(dr.determinant()) * energyOf(J);
      minJ = std::min(minJ, J.determinant());
    }
  };
  totals(rep.energyBefore, rep.minJacobianBefore);
  if (!std::isfinite(rep.energyBefore)) {  // a fold in the region: nothing to relax from
    rep.energyAfter = rep.energyBefore;
    rep.minJacobianAfter = rep.minJacobianBefore;
    return rep;
  }

  Star star;
  double previous = rep.energyBefore;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    ++rep.sweeps;
    for (int v : region) {
      star.tris.clear();
      for (Index k = topology.start[std::size_t(v)]; k < topology.start[std::size_t(v) + 1]; ++k) {
        const std::array<int, 3>& t = tri(topology.around[std::size_t(k)]);
        const int at = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        const int a = t[std::size_t((at + 1) % 3)], b = t[std::size_t((at + 2) % 3)];
        Mat2 dr;
        dr << restX(a, 0) - restX(v, 0), restX(b, 0) - restX(v, 0), restX(a, 1) - restX(v, 1), restX(b, 1) - restX(v, 1);
        star.tris.push_back({P.row(a).transpose(), P.row(b).transpose(), dr.inverse(), 0.5 * std::abs(dr.determinant())});
      }
      const Vec2 p = P.row(v).transpose();
      const double e0 = star.energy(p);
      if (!std::isfinite(e0)) continue;
      const Vec2 g = star.gradient(p);
      const double reach = star.reach(p);
      if (!(g.norm() > 0.0) || !(reach > 0.0)) continue;
      // Newton with a difference Hessian (exact gradients, symmetrized); the gradient when it is
      // not positive definite.
      const double h = 1e-5 * reach;
      Mat2 H;
      H.col(0) = (star.gradient(p + Vec2(h, 0.0)) - g) / h;
      H.col(1) = (star.gradient(p + Vec2(0.0, h)) - g) / h;
      H = 0.5 * (H + H.transpose()).eval();
      Vec2 step;
      if (H.allFinite() && H(0, 0) > 0.0 && H.determinant() > 0.0) step = -H.ldlt().solve(g);
      else step = -g / g.norm() * reach;
      if (const double n = step.norm(); n > 0.5 * reach) step *= 0.5 * reach / n;
      const bool border = topology.free[std::size_t(v)] == 2;
      const Vec2 normal = border ? exteriorOutwardAt(topology.frame, restX.row(v).transpose()) : Vec2::Zero();
      for (double s = 1.0; s > 1e-6; s *= 0.5) {
        Vec2 q = p + s * step;
        if (border) q -= std::min(0.0, normal.dot(q - restX.row(v).transpose())) * normal;  // not inward of the border line
        if (star.energy(q) < e0) {
          P.row(v) = q.transpose();
          break;
        }
      }
    }
    double energy = 0.0, minJ = 0.0;
    totals(energy, minJ);
    const bool settled = previous - energy <= kSettled * previous;
    previous = energy;
    if (settled) break;
  }
  totals(rep.energyAfter, rep.minJacobianAfter);
  return rep;
}

}  // namespace kc
