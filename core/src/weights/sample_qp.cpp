#include "kc/core/weights/sample_qp.h"

#include "simd2.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <vector>

namespace kc {
using detail::D2;
using detail::load2;
using detail::store2;
namespace {

/// The dual at λ: f = ½|max(0, z)|² − bᵀλ with z = w0 + Aᵀλ, its gradient g = A max(0, z) − b
/// and the generalized Hessian A_S A_Sᵀ over S = {z > 0} as six sums (xx, xy, x, yy, y, 1),
/// filled by hessianSums only when a Newton step is taken from this point.
struct DualPoint {
  Eigen::Vector3d lambda;
  double f = 0.0;
  Eigen::Vector3d g;
  double h[6] = {0, 0, 0, 0, 0, 0};
};

template <class M>
inline D2 select(D2 v, M mask) {
  return reinterpret_cast<D2>(reinterpret_cast<M>(v) & mask);
}

/// One O(m) pass: the dual value and gradient at p.lambda; writes w = max(0, z), the primal
/// point of this λ (the last evaluation is the returned solution). Kept to four accumulators so
/// the loop stays in registers; the Hessian sums come from a second pass (hessianSums) that is
/// only needed when another Newton step follows.
void evaluateDual(const ControlFrame& frame, const double* w0, double* w, const Eigen::Vector3d& b, DualPoint& p) {
  const Index m = frame.size();
  const double *cx = frame.cx(), *cy = frame.cy();
  const double l0 = p.lambda(0), l1 = p.lambda(1), l2 = p.lambda(2);
  const D2 L0 = {l0, l0}, L1 = {l1, l1}, L2 = {l2, l2}, zero = {0.0, 0.0};
  D2 f = zero, gx = zero, gy = zero, g1 = zero;
  Index i = 0;
  for (; i + 1 < m; i += 2) {
    const D2 x = load2(cx + i), y = load2(cy + i);
    const D2 z = load2(w0 + i) + (L0 * x + L1 * y + L2);
    const D2 zp = select(z, z > zero);
    store2(w + i, zp);
    f += zp * zp;
    gx += zp * x;
    gy += zp * y;
    g1 += zp;
  }
  double t[4] = {f[0] + f[1], gx[0] + gx[1], gy[0] + gy[1], g1[0] + g1[1]};
  if (i < m) {
    const double z = w0[i] + (l0 * cx[i] + l1 * cy[i] + l2);
    const double zp = z > 0.0 ? z : 0.0;
    w[i] = zp;
    t[0] += zp * zp;
    t[1] += zp * cx[i];
    t[2] += zp * cy[i];
    t[3] += zp;
  }
  p.f = 0.5 * t[0] - b.dot(p.lambda);
  p.g = Eigen::Vector3d(t[1] - b(0), t[2] - b(1), t[3] - b(2));
}

/// The generalized Hessian A_S A_Sᵀ over S = {i : w_i > 0} (w from evaluateDual) as six sums.
void hessianSums(const ControlFrame& frame, const double* w, DualPoint& p) {
  const Index m = frame.size();
  const double *cx = frame.cx(), *cy = frame.cy(), *cxx = frame.cxx(), *cxy = frame.cxy(), *cyy = frame.cyy();
  const D2 zero = {0.0, 0.0}, one = {1.0, 1.0};
  D2 hxx = zero, hxy = zero, hx = zero, hyy = zero, hy = zero, h1 = zero;
  Index i = 0;
  for (; i + 1 < m; i += 2) {
    const auto on = load2(w + i) > zero;
    hxx += select(load2(cxx + i), on);
    hxy += select(load2(cxy + i), on);
    hx += select(load2(cx + i), on);
    hyy += select(load2(cyy + i), on);
    hy += select(load2(cy + i), on);
    h1 += select(one, on);
  }
  double* h = p.h;
  h[0] = hxx[0] + hxx[1];
  h[1] = hxy[0] + hxy[1];
  h[2] = hx[0] + hx[1];
  h[3] = hyy[0] + hyy[1];
  h[4] = hy[0] + hy[1];
  h[5] = h1[0] + h1[1];
  if (i < m && w[i] > 0.0) {
    h[0] += cxx[i];
    h[1] += cxy[i];
    h[2] += cx[i];
    h[3] += cyy[i];
    h[4] += cy[i];
    h[5] += 1.0;
  }
}

/// Solves (H + δI) d = rhs for the symmetric positive semidefinite H given as six sums: by the
/// adjugate when H is well conditioned, else by a 3×3 LDLᵀ factorization with pivot checks;
/// δ > 0 only when a pivot falls below 1e-12·trace,
/// i.e. H is (nearly) singular (Levenberg term for rank-deficient positive sets).
Eigen::Vector3d newtonStep(const double* h, const Eigen::Vector3d& rhs) {
  {
    // Fast path for a well-conditioned H (Hadamard ratio det H / (h00 h11 h22) ≥ 1e-6): the
    // adjugate needs a single division.
    const double a00 = h[0], a01 = h[1], a02 = h[2], a11 = h[3], a12 = h[4], a22 = h[5];
    const double c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22, c02 = a01 * a12 - a02 * a11;
    const double det = a00 * c00 + a01 * c01 + a02 * c02;
    if (det > 1e-6 * a00 * a11 * a22 && det > 0.0) {
      const double c11 = a00 * a22 - a02 * a02, c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
      const double id = 1.0 / det;
      return Eigen::Vector3d((c00 * rhs(0) + c01 * rhs(1) + c02 * rhs(2)) * id,
                             (c01 * rhs(0) + c11 * rhs(1) + c12 * rhs(2)) * id,
                             (c02 * rhs(0) + c12 * rhs(1) + c22 * rhs(2)) * id);
    }
  }
  const double trace = h[0] + h[3] + h[5];
  const double floor = 1e-12 * (trace + 1e-300);
  double delta = 0.0;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const double a00 = h[0] + delta, a10 = h[1], a20 = h[2], a11 = h[3] + delta, a21 = h[4], a22 = h[5] + delta;
    if (a00 > floor) {
      const double i0 = 1.0 / a00;
      const double l10 = a10 * i0, l20 = a20 * i0;
      const double d1 = a11 - l10 * a10;
      if (d1 > floor) {
        const double i1 = 1.0 / d1;
        const double l21 = (a21 - l20 * a10) * i1;
        const double d2 = a22 - l20 * a20 - l21 * l21 * d1;
        if (d2 > floor) {
          // L D Lᵀ d = rhs.
          const double y0 = rhs(0), y1 = rhs(1) - l10 * y0, y2 = rhs(2) - l20 * y0 - l21 * y1;
          const double z2 = y2 / d2, z1 = y1 * i1 - l21 * z2, z0 = y0 * i0 - l10 * z1 - l20 * z2;
          return Eigen::Vector3d(z0, z1, z2);
        }
      }
    }
    delta = 1e-10 * (trace + 1.0);
  }
  // Unreachable in exact arithmetic (H + δI is positive definite); a gradient step otherwise.
  return rhs / (1e-10 * (trace + 1.0));
}

/// Dual semismooth Newton for the projection of w0 onto {w ≥ 0, Aw = b}, from the evaluated
/// point p (w already holds max(0, z) of p). Returns true when |A w − b|∞ ≤ tolerance.
bool dualNewton(const ControlFrame& frame, const Eigen::Vector3d& b, const double* w0, double* w, DualPoint& p,
                const QpOptions& options, SampleReport& report) {
  DualPoint trial;
  int it = 0;
  bool ok = p.g.lpNorm<Eigen::Infinity>() <= options.tolerance;
  while (!ok && it < options.maxIterations) {
    ++it;
    hessianSums(frame, w, p);  // w = max(0, z) of p
    const Eigen::Vector3d d = newtonStep(p.h, -p.g);
    const double slope = p.g.dot(d);  // < 0: H + δI is positive definite
    double t = 1.0;
    const double gNorm = p.g.lpNorm<Eigen::Infinity>();
    for (int ls = 0; ls < 80; ++ls) {
      trial.lambda = p.lambda + t * d;
      evaluateDual(frame, w0, w, b, trial);
      if (trial.f <= p.f + 1e-4 * t * slope) break;
      // Near the optimum f changes below its rounding error: judge by the gradient instead.
      if (std::abs(trial.f - p.f) <= 1e-13 * (std::abs(p.f) + 1.0) && trial.g.lpNorm<Eigen::Infinity>() < gNorm) break;
      const double curvature = trial.f - p.f - slope * t;
      const double tNew = curvature > 0.0 ? -slope * t * t / (2.0 * curvature) : 0.5 * t;
      t = std::clamp(tNew, 0.1 * t, 0.5 * t);
    }
    std::swap(p, trial);  // w holds max(0, z) of the last evaluation, which is the new p
    ok = p.g.lpNorm<Eigen::Infinity>() <= options.tolerance;
  }
  report.iterations = it;
  report.residual = p.g.lpNorm<Eigen::Infinity>();
  return ok;
}

}  // namespace

SampleReport sampleQp(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, std::span<double> w,
                      const QpOptions& options) {
  const Index m = frame.size();
  assert(static_cast<Index>(w0.size()) == m && static_cast<Index>(w.size()) == m);
  SampleReport report;
  // Start at the QEC multipliers: a non-negative QEC solution is already the optimum (and then x̂
  // is in the hull, so the hull test is skipped).
  const Eigen::Vector3d b(xh.x(), xh.y(), 1.0);
  DualPoint p;
  p.lambda = qecMultipliers(frame, xh, w0);
  evaluateDual(frame, w0.data(), w.data(), b, p);
  if (p.g.lpNorm<Eigen::Infinity>() <= options.tolerance) {
    report.residual = p.g.lpNorm<Eigen::Infinity>();
    return report;
  }
  const double excess = frame.hullExcess(xh);
  if (!(excess > 0.0)) {
    if (dualNewton(frame, b, w0.data(), w.data(), p, options, report)) return report;
  } else {
    // Fallback (see header): u = w + t1 ≥ 0 solves the QP at βx̂ on the hull boundary with the
    // target β(w0 + t1), scaled by 1/β; t = (1 − β)/(mβ).
    const double beta = frame.hullShrink(xh);
    const double t = (1.0 - beta) / (static_cast<double>(m) * beta);
    const Vec2 y = beta * xh;
    constexpr Index kStack = 64;
    double stack[kStack];
    std::vector<double> heap;
    double* v0 = stack;
    if (m > kStack) {
      heap.resize(static_cast<std::size_t>(m));
      v0 = heap.data();
    }
    for (Index i = 0; i < m; ++i) v0[i] = beta * (w0[i] + t);
    const std::span<const double> v0s(v0, static_cast<std::size_t>(m));
    const Eigen::Vector3d by(y.x(), y.y(), 1.0);
    DualPoint q;
    q.lambda = qecMultipliers(frame, y, v0s);
    evaluateDual(frame, v0, w.data(), by, q);
    const bool ok = dualNewton(frame, by, v0, w.data(), q, options, report);
    report.residual /= beta;
    if (excess > options.hullTolerance) {
      for (Index i = 0; i < m; ++i) w[i] = w[i] / beta - t;
      report.status = SampleStatus::Infeasible;
    } else {
      // On the hull boundary up to rounding: t is a rounding-level shift, so keep w ≥ 0 exact.
      for (Index i = 0; i < m; ++i) w[i] = std::max(0.0, w[i] / beta - t);
    }
    if (ok) return report;
  }
  // Not certified: the QEC solution keeps partition of unity and reproduction exact.
  sampleQec(frame, xh, w0, w);
  report.status = SampleStatus::Failed;
  report.residual = 0.0;
  return report;
}

}  // namespace kc
