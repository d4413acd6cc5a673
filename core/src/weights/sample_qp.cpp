#include "kc/core/weights/sample_qp.h"

#include "simd2.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <cassert>
#include <cmath>
#include <cstring>
#include <vector>

#include <Eigen/Eigenvalues>

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
///
/// Incremental: p.lambda = λ + d where w holds max(0, z) of λ on entry; z on the positive set
/// S = {i : w_i > 0} is updated as z_S = w_S + A_Sᵀd, elsewhere z = w0 + Aᵀ(λ + d). Both give
/// the same point in exact arithmetic; the incremental form keeps the digits that w0 + Aᵀλ
/// loses to cancellation when |λ| is large. That happens when x̂ lies on or near the hull
/// boundary: the optimal λ then runs far along the boundary's normal, and the plain
/// evaluation's residual stalls at about ε|λ|, above the tolerance.
/// Weighted (a ≠ nullptr, the allowance metric Σ (w − w0)²/a): z = w0 + a ⊙ Aᵀλ and
/// f = ½ Σ max(0, z)²/a − bᵀλ, whose gradient is again A w − b.
template <bool Incremental, bool Weighted>
void evaluateImpl(const ControlFrame& frame, const double* w0, const double* a, double* w, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& d, DualPoint& p) {
  const Index m = frame.size();
  const double *cx = frame.cx(), *cy = frame.cy();
  const double l0 = p.lambda(0), l1 = p.lambda(1), l2 = p.lambda(2);
  const D2 L0 = {l0, l0}, L1 = {l1, l1}, L2 = {l2, l2}, zero = {0.0, 0.0};
  const D2 S0 = {d(0), d(0)}, S1 = {d(1), d(1)}, S2 = {d(2), d(2)};
  D2 f = zero, gx = zero, gy = zero, g1 = zero;
  Index i = 0;
  for (; i + 1 < m; i += 2) {
    const D2 x = load2(cx + i), y = load2(cy + i);
    // Unweighted, the products by a are left out (the same bits as by 1, one multiply fewer).
    const auto scaled = [&](D2 v) {
      if constexpr (Weighted) v *= load2(a + i);
      return v;
    };
    D2 z = load2(w0 + i) + scaled(L0 * x + L1 * y + L2);
    if constexpr (Incremental) {
      const D2 wi = load2(w + i);
      const auto on = wi > zero;
      z = select(wi + scaled(S0 * x + S1 * y + S2), on) + select(z, ~on);
    }
    const D2 zp = select(z, z > zero);
    store2(w + i, zp);
    if constexpr (Weighted) f += zp * zp / load2(a + i);
    else f += zp * zp;
    gx += zp * x;
    gy += zp * y;
    g1 += zp;
  }
  double t[4] = {f[0] + f[1], gx[0] + gx[1], gy[0] + gy[1], g1[0] + g1[1]};
  if (i < m) {
    const double ai = Weighted ? a[i] : 1.0;  // × 1 and / 1 are exact
    double z = w0[i] + ai * (l0 * cx[i] + l1 * cy[i] + l2);
    if (Incremental && w[i] > 0.0) z = w[i] + ai * (d(0) * cx[i] + d(1) * cy[i] + d(2));
    const double zp = z > 0.0 ? z : 0.0;
    w[i] = zp;
    t[0] += zp * zp / ai;
    t[1] += zp * cx[i];
    t[2] += zp * cy[i];
    t[3] += zp;
  }
  p.f = 0.5 * t[0] - b.dot(p.lambda);
  p.g = Eigen::Vector3d(t[1] - b(0), t[2] - b(1), t[3] - b(2));
}

template <bool Incremental>
void evaluate(const ControlFrame& frame, const double* w0, const double* a, double* w, const Eigen::Vector3d& b,
              const Eigen::Vector3d& d, DualPoint& p) {
  if (a) evaluateImpl<Incremental, true>(frame, w0, a, w, b, d, p);
  else evaluateImpl<Incremental, false>(frame, w0, a, w, b, d, p);
}

void evaluateDual(const ControlFrame& frame, const double* w0, const double* a, double* w, const Eigen::Vector3d& b,
                  DualPoint& p) {
  evaluate<false>(frame, w0, a, w, b, Eigen::Vector3d::Zero(), p);
}

/// Σ a_i A_i A_iᵀ (A_i = (x_i, y_i, 1)) as six sums, over the i with w_i > 0 (over all when w is null).
void weightedMoments(const ControlFrame& frame, const double* a, const double* w, double* h) {
  const Index m = frame.size();
  const double *cx = frame.cx(), *cy = frame.cy(), *cxx = frame.cxx(), *cxy = frame.cxy(), *cyy = frame.cyy();
  std::fill(h, h + 6, 0.0);
  for (Index i = 0; i < m; ++i) {
    if (w && !(w[i] > 0.0)) continue;
    const double ai = a[i];
    h[0] += ai * cxx[i];
    h[1] += ai * cxy[i];
    h[2] += ai * cx[i];
    h[3] += ai * cyy[i];
    h[4] += ai * cy[i];
    h[5] += ai;
  }
}

/// The generalized Hessian A_S A_Sᵀ over S = {i : w_i > 0} (w from evaluateDual) as six sums;
/// weighted, Σ over S of a_i A_i A_iᵀ.
void hessianSums(const ControlFrame& frame, const double* a, const double* w, DualPoint& p) {
  if (a) {
    weightedMoments(frame, a, w, p.h);
    return;
  }
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

/// Solves H d = rhs for the symmetric H given as six sums by the adjugate when H is well
/// conditioned (Hadamard ratio det H / (h00 h11 h22) ≥ 1e-6: a single division). Returns false
/// otherwise.
bool adjugateStep(const double* h, const Eigen::Vector3d& rhs, Eigen::Vector3d& d) {
  const double a00 = h[0], a01 = h[1], a02 = h[2], a11 = h[3], a12 = h[4], a22 = h[5];
  const double c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22, c02 = a01 * a12 - a02 * a11;
  const double det = a00 * c00 + a01 * c01 + a02 * c02;
  if (!(det > 1e-6 * a00 * a11 * a22 && det > 0.0)) return false;
  const double c11 = a00 * a22 - a02 * a02, c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
  const double id = 1.0 / det;
  d = Eigen::Vector3d((c00 * rhs(0) + c01 * rhs(1) + c02 * rhs(2)) * id, (c01 * rhs(0) + c11 * rhs(1) + c12 * rhs(2)) * id,
                      (c02 * rhs(0) + c12 * rhs(1) + c22 * rhs(2)) * id);
  return true;
}

/// Solves H d = rhs for the symmetric positive semidefinite H given as six sums: by the adjugate
/// when H is well conditioned, else by a 3×3 LDLᵀ factorization. Returns false when a pivot falls
/// below 1e-12·trace, i.e. H is (nearly) singular.
bool spdStep(const double* h, const Eigen::Vector3d& rhs, Eigen::Vector3d& d) {
  if (adjugateStep(h, rhs, d)) return true;
  const double trace = h[0] + h[3] + h[5];
  const double floor = 1e-12 * (trace + 1e-300);
  const double a00 = h[0], a10 = h[1], a20 = h[2], a11 = h[3], a21 = h[4], a22 = h[5];
  if (!(a00 > floor)) return false;
  const double i0 = 1.0 / a00;
  const double l10 = a10 * i0, l20 = a20 * i0;
  const double d1 = a11 - l10 * a10;
  if (!(d1 > floor)) return false;
  const double i1 = 1.0 / d1;
  const double l21 = (a21 - l20 * a10) * i1;
  const double d2 = a22 - l20 * a20 - l21 * l21 * d1;
  if (!(d2 > floor)) return false;
  // L D Lᵀ d = rhs.
  const double y0 = rhs(0), y1 = rhs(1) - l10 * y0, y2 = rhs(2) - l20 * y0 - l21 * y1;
  const double z2 = y2 / d2, z1 = y1 * i1 - l21 * z2, z0 = y0 * i0 - l10 * z1 - l20 * z2;
  d = Eigen::Vector3d(z0, z1, z2);
  return true;
}

/// −g split by the eigenvectors of a singular H: the minimum-norm Newton step −H⁺g on H's range
/// (eigenvalues above 1e-10 of the largest) and the steepest descent −P_N g in its null space N.
struct SingularStep {
  Eigen::Vector3d range = Eigen::Vector3d::Zero();
  Eigen::Vector3d null = Eigen::Vector3d::Zero();
};

SingularStep splitStep(const double* h, const Eigen::Vector3d& g) {
  Eigen::Matrix3d H;
  H << h[0], h[1], h[2], h[1], h[3], h[4], h[2], h[4], h[5];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(H);
  const Eigen::Vector3d& ev = eig.eigenvalues();
  SingularStep s;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d v = eig.eigenvectors().col(k);
    if (ev(k) > 1e-10 * ev(2))
      s.range -= (v.dot(g) / ev(k)) * v;
    else
      s.null -= v.dot(g) * v;
  }
  return s;
}

/// The Newton direction at p (p.h: Hessian sums; w = max(0, z) of p). When H is singular (the
/// positive set S lies on a line or has fewer than two controls, e.g. near a hull edge or
/// vertex) f is linear along H's null space on the current piece, so the model has no minimizer
/// there: the direction is the range step plus the null-space descent taken to the minimizer
/// past the first breakpoint (ratio test over the inactive controls: the smallest s ≥ 0 with
/// z_i + a_iᵀ(range + s·null) = 0). A fixed Levenberg term would crawl instead when the
/// null-space gradient is small (a sample within ~1e-10 of an edge line).
Eigen::Vector3d newtonDirection(const ControlFrame& frame, const double* w0, const double* a, const double* w,
                                const DualPoint& p) {
  Eigen::Vector3d d;
  if (spdStep(p.h, -p.g, d)) return d;
  const SingularStep s = splitStep(p.h, p.g);
  if (s.null.squaredNorm() == 0.0) return s.range;
  const Index m = frame.size();
  const double *cx = frame.cx(), *cy = frame.cy();
  const Eigen::Vector3d l = p.lambda + s.range;
  // Controls on the line of S have rate 0 up to rounding: they never activate along the null space.
  const double noise = 1e-12 * s.null.lpNorm<1>();
  double first = std::numeric_limits<double>::infinity(), firstRate = 0.0, firstA = 1.0;
  for (Index i = 0; i < m; ++i) {
    if (w[i] > 0.0) continue;
    const double ai = a ? a[i] : 1.0;
    const double rate = ai * (s.null(0) * cx[i] + s.null(1) * cy[i] + s.null(2));
    if (!(rate > ai * noise * (std::abs(cx[i]) + std::abs(cy[i]) + 1.0))) continue;
    const double z = w0[i] + ai * (l(0) * cx[i] + l(1) * cy[i] + l(2));
    const double at = std::max(0.0, -z) / rate;
    if (at < first) {
      first = at;
      firstRate = rate;
      firstA = ai;
    }
  }
  // No breakpoint: f decreases along the null space without bound (x̂ outside the hull up to
  // rounding); a long step, which the line search shortens.
  if (!std::isfinite(first)) return s.range + 1e10 * s.null;
  // Along s·null, f' = −|null|² up to the breakpoint, then −|null|² + rate²(s − first)/a: its
  // minimizer if no other control activates on the way (the line search checks). firstA is 1
  // unweighted (× 1 is exact).
  return s.range + (first + firstA * s.null.squaredNorm() / (firstRate * firstRate)) * s.null;
}

/// The minimum-norm solution −H⁺g: the Newton step when H is regular; when it is singular, the
/// range part only, which does not move λ along the null space (where g holds only rounding
/// noise once the positive set is the optimal one).
Eigen::Vector3d rangeStep(const double* h, const Eigen::Vector3d& g) {
  Eigen::Vector3d d;
  if (spdStep(h, -g, d)) return d;
  return splitStep(h, g).range;
}

/// Below this gradient norm, Newton first tries to finish in one step (polish).
constexpr double kPolishGradient = 1e-6;

enum class Polish { Certified, Improved, Rejected };

/// Near the optimum, the full step on the current positive set S: λ + H⁺(−g), evaluated
/// incrementally on S (evaluate<true>). Certified: |A w − b|∞ ≤ tolerance. Improved: not
/// certified but |g|∞ decreased (e.g. a control with a rounding-level weight left S), so the
/// point is taken as the next iterate; the line search could not judge it, because f itself
/// carries the rounding error ε|bᵀλ|. In both cases the result is in `trial` and w. Rejected:
/// w is restored to max(0, z) of p. p.h must hold the Hessian sums of p.
Polish polish(const ControlFrame& frame, const Eigen::Vector3d& b, const double* w0, const double* a, double* w, DualPoint& p,
              DualPoint& trial, double tolerance) {
  const Eigen::Vector3d d = rangeStep(p.h, p.g);
  trial.lambda = p.lambda + d;
  evaluate<true>(frame, w0, a, w, b, d, trial);
  const double g = trial.g.lpNorm<Eigen::Infinity>();
  if (g <= tolerance) return Polish::Certified;
  if (g < p.g.lpNorm<Eigen::Infinity>()) return Polish::Improved;
  evaluateDual(frame, w0, a, w, b, p);
  return Polish::Rejected;
}

/// The infeasible fallback's point βx̂ is moved this fraction of its length into the hull (64
/// units of rounding; see sampleQp).
constexpr double kHullInset = 64.0 * std::numeric_limits<double>::epsilon();

/// An iterate that ends the iterations within this factor of the tolerance is accepted: the
/// positive set can cycle among controls whose weights are at rounding level (|z_i| ~ 1e-14, e.g.
/// an exterior sample whose target has many exact zeros), which holds the residual at ~1e-13
/// without any step improving it.
constexpr double kStallFactor = 10.0;

/// Dual semismooth Newton for the projection of w0 onto {w ≥ 0, Aw = b}, from the evaluated
/// point p (w already holds max(0, z) of p). Returns true when |A w − b|∞ ≤ tolerance, or when the
/// iterations end with it ≤ kStallFactor · tolerance.
bool dualNewton(const ControlFrame& frame, const Eigen::Vector3d& b, const double* w0, const double* a, double* w, DualPoint& p,
                const QpOptions& options, SampleReport& report) {
  DualPoint trial;
  int it = 0;
  bool ok = p.g.lpNorm<Eigen::Infinity>() <= options.tolerance;
  while (!ok && it < options.maxIterations) {
    ++it;
    hessianSums(frame, a, w, p);  // w = max(0, z) of p
    if (p.g.lpNorm<Eigen::Infinity>() <= kPolishGradient) {
      const Polish result = polish(frame, b, w0, a, w, p, trial, options.tolerance);
      if (result != Polish::Rejected) {
        std::swap(p, trial);
        ok = result == Polish::Certified;
        continue;
      }
    }
    const Eigen::Vector3d d = newtonDirection(frame, w0, a, w, p);
    const double slope = p.g.dot(d);  // < 0: a descent direction
    double t = 1.0;
    const double gNorm = p.g.lpNorm<Eigen::Infinity>();
    for (int ls = 0; ls < 80; ++ls) {
      trial.lambda = p.lambda + t * d;
      evaluateDual(frame, w0, a, w, b, trial);
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
  return ok || report.residual <= kStallFactor * options.tolerance;
}

/// The multipliers of the equality-constrained weighted problem (QEC in the metric 1/a):
/// λ = (A diag(a) Aᵀ)⁻¹ (b − A w0); the plain QEC multipliers without a.
Eigen::Vector3d startMultipliers(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, const double* a) {
  if (!a) return qecMultipliers(frame, xh, w0);
  const Index m = frame.size();
  const double *cx = frame.cx(), *cy = frame.cy();
  double h[6];
  weightedMoments(frame, a, nullptr, h);
  double sx = 0.0, sy = 0.0, s1 = 0.0;
  for (Index i = 0; i < m; ++i) {
    sx += w0[i] * cx[i];
    sy += w0[i] * cy[i];
    s1 += w0[i];
  }
  Eigen::Vector3d lambda;
  if (!spdStep(h, Eigen::Vector3d(xh.x() - sx, xh.y() - sy, 1.0 - s1), lambda)) return qecMultipliers(frame, xh, w0);
  return lambda;
}

/// min Σ (w − w0)²/a (a null: Euclidean) s.t. Aw = b at x̂, w ≥ −t, through u = w + t1 ≥ 0: the
/// QP at βx̂ with the target β(w0 + t1), β = 1/(1 + m t) (the centroid is the frame's origin, so
/// 1ᵀβu = 1 and Ĉβu = βx̂), whose solution is scaled back by 1/β. βx̂ must lie in the hull.
/// Writes w = u/β − t; report.residual is in the original problem's units.
bool shiftedQp(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, const double* a, double beta, double t,
               std::span<double> w, const QpOptions& options, SampleReport& report) {
  const Index m = frame.size();
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
  q.lambda = startMultipliers(frame, y, v0s, a);
  evaluateDual(frame, v0, a, w.data(), by, q);
  const bool ok = dualNewton(frame, by, v0, a, w.data(), q, options, report);
  report.residual /= beta;
  for (Index i = 0; i < m; ++i) w[i] = w[i] / beta - t;
  return ok;
}
}  // namespace

SampleReport sampleQp(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, std::span<double> w,
                      const QpOptions& options) {
  return sampleQpWeighted(frame, xh, w0, {}, w, options);
}

SampleReport sampleQpWeighted(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0,
                              std::span<const double> allowance, std::span<double> w, const QpOptions& options) {
  const Index m = frame.size();
  assert(static_cast<Index>(w0.size()) == m && static_cast<Index>(w.size()) == m);
  assert(allowance.empty() || static_cast<Index>(allowance.size()) == m);
  const double* a = allowance.empty() ? nullptr : allowance.data();
  SampleReport report;
  // Start at the QEC multipliers: a non-negative QEC solution is already the optimum (and then x̂
  // is in the hull, so the hull test is skipped).
  const Eigen::Vector3d b(xh.x(), xh.y(), 1.0);
  DualPoint p;
  p.lambda = startMultipliers(frame, xh, w0, a);
  evaluateDual(frame, w0.data(), a, w.data(), b, p);
  if (p.g.lpNorm<Eigen::Infinity>() <= options.tolerance) {
    report.residual = p.g.lpNorm<Eigen::Infinity>();
    return report;
  }
  const double excess = frame.hullExcess(xh);
  if (a) {
    // Weighted: inside the hull, Newton in the metric; a sample it does not certify, and one
    // outside the hull (whose fallback solves at a point of the hull's boundary, where the
    // feasible set is one edge's or vertex's weights whatever the metric), gets the Euclidean QP.
    if (!(excess > 0.0) && dualNewton(frame, b, w0.data(), a, w.data(), p, options, report)) return report;
    return sampleQp(frame, xh, w0, w, options);
  }
  // The plain QP from here on (a is null).
  if (!(excess > 0.0)) {
    if (dualNewton(frame, b, w0.data(), nullptr, w.data(), p, options, report)) return report;
  } else {
    // Fallback (see header): u = w + t1 ≥ 0 solves the QP at βx̂ on the hull boundary with the
    // target β(w0 + t1), scaled by 1/β; t = (1 − β)/(mβ).
    // βx̂ lies on the hull's boundary, where the feasible set is one edge's controls or one
    // vertex; rounded, it can lie just outside in A u's arithmetic, where Newton cannot converge
    // (its multipliers run off along the edge's normal, the residual stalls near 1e-12). Moved
    // inwards by kHullInset of its length it is feasible there, and t changes by O(kHullInset).
    const double beta = frame.hullShrink(xh) * (1.0 - kHullInset);
    const double t = (1.0 - beta) / (static_cast<double>(m) * beta);
    const bool ok = shiftedQp(frame, xh, w0, nullptr, beta, t, w, options, report);
    if (excess > options.hullTolerance) {
      report.status = SolveStatus::Infeasible;
    } else {
      // On the hull boundary up to rounding: t is a rounding-level shift, so keep w ≥ 0 exact.
      for (Index i = 0; i < m; ++i) w[i] = std::max(0.0, w[i]);
    }
    if (ok) return report;
  }
  // Not certified: the last iterate projected onto Aw = b (QEC with the iterate as target) keeps
  // partition of unity and reproduction exact and moves w only by the small residual, so the
  // weights keep the QP's character (local, non-negative up to that residual).
  sampleQec(frame, xh, w, w);
  report.status = SolveStatus::NotConverged;
  return report;
}

}  // namespace kc

namespace kc {

SampleReport sampleQpAbove(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, double bound,
                           std::span<const double> allowance, std::span<double> w, const QpOptions& options) {
  const Index m = frame.size();
  assert(static_cast<Index>(w0.size()) == m && static_cast<Index>(w.size()) == m);
  assert(allowance.empty() || static_cast<Index>(allowance.size()) == m);
  if (!(bound <= 0.0)) throw std::invalid_argument("sampleQpAbove: the bound must be <= 0");
  // The least slack t that makes w ≥ −t feasible at x̂ (0 inside the hull), kHullInset above it.
  const double shrink = frame.hullShrink(xh) * (1.0 - kHullInset);
  const double t = std::max(-bound, (1.0 - shrink) / (static_cast<double>(m) * shrink));
  SampleReport report;
  if (shiftedQp(frame, xh, w0, allowance.empty() ? nullptr : allowance.data(), 1.0 / (1.0 + static_cast<double>(m) * t), t, w,
                options, report))
    return report;
  if (!allowance.empty()) return sampleQpAbove(frame, xh, w0, bound, {}, w, options);
  // Not certified: as sampleQp, the iterate projected onto Aw = b.
  sampleQec(frame, xh, w, w);
  report.status = SolveStatus::NotConverged;
  return report;
}

}  // namespace kc
