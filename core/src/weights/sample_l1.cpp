#include "kc/core/weights/sample_l1.h"

#include <array>
#include <cassert>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace kc {
namespace {

/// Inverse of the 3×3 matrix whose columns are a_i = (x_i, y_i, 1), by cofactors; returns the
/// determinant (0 when singular, inverse then unspecified).
double invertColumns(const double* cx, const double* cy, const std::array<int, 3>& idx, Eigen::Matrix3d& inv) {
  Eigen::Matrix3d B;
  for (int k = 0; k < 3; ++k) B.col(k) = Eigen::Vector3d(cx[idx[k]], cy[idx[k]], 1.0);
  const double c00 = B(1, 1) * B(2, 2) - B(1, 2) * B(2, 1);
  const double c01 = B(1, 2) * B(2, 0) - B(1, 0) * B(2, 2);
  const double c02 = B(1, 0) * B(2, 1) - B(1, 1) * B(2, 0);
  const double det = B(0, 0) * c00 + B(0, 1) * c01 + B(0, 2) * c02;
  if (det == 0.0) return 0.0;
  const double id = 1.0 / det;
  inv(0, 0) = c00 * id;
  inv(1, 0) = c01 * id;
  inv(2, 0) = c02 * id;
  inv(0, 1) = (B(0, 2) * B(2, 1) - B(0, 1) * B(2, 2)) * id;
  inv(1, 1) = (B(0, 0) * B(2, 2) - B(0, 2) * B(2, 0)) * id;
  inv(2, 1) = (B(0, 1) * B(2, 0) - B(0, 0) * B(2, 1)) * id;
  inv(0, 2) = (B(0, 1) * B(1, 2) - B(0, 2) * B(1, 1)) * id;
  inv(1, 2) = (B(0, 2) * B(1, 0) - B(0, 0) * B(1, 2)) * id;
  inv(2, 2) = (B(0, 0) * B(1, 1) - B(0, 1) * B(1, 0)) * id;
  return det;
}

// Two-lane double vectors (GCC/Clang vector extensions; SSE2 on x86-64).
using D2 = double __attribute__((vector_size(16)));
inline D2 load2(const double* p) {
  D2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// max_i |y0 x_i + y1 y_i + y2| over the m normalized controls.
double maxAbsAffine(const double* cx, const double* cy, Index m, const Eigen::Vector3d& y) {
  const D2 Y0 = {y(0), y(0)}, Y1 = {y(1), y(1)}, Y2 = {y(2), y(2)};
  D2 hi = {0.0, 0.0}, lo = hi;
  Index i = 0;
  for (; i + 1 < m; i += 2) {
    const D2 s = Y0 * load2(cx + i) + Y1 * load2(cy + i) + Y2;
    hi = s > hi ? s : hi;
    lo = s < lo ? s : lo;
  }
  double best = std::max(std::max(hi[0], hi[1]), -std::min(lo[0], lo[1]));
  if (i < m) best = std::max(best, std::abs(y(0) * cx[i] + y(1) * cy[i] + y(2)));
  return best;
}

/// Twice the area of the normalized triangle (i, j, k): the determinant of [a_i a_j a_k].
double triangleDet(const double* cx, const double* cy, int i, int j, int k) {
  return (cx[j] - cx[i]) * (cy[k] - cy[i]) - (cx[k] - cx[i]) * (cy[j] - cy[i]);
}

/// Starting basis: the three controls with the largest |QEC correction| (the ℓ2 analogue of the
/// ℓ1 optimum's support), replaced by the frame's well-shaped triangle when they are nearly
/// collinear.
std::array<int, 3> startingBasis(const ControlFrame& frame, const Eigen::Vector3d& lambda) {
  const Index m = frame.size();
  const double* cx = frame.cx();
  const double* cy = frame.cy();
  std::array<int, 3> best = {-1, -1, -1};
  std::array<double, 3> val = {-1.0, -1.0, -1.0};
  for (Index i = 0; i < m; ++i) {
    const double v = std::abs(lambda(0) * cx[i] + lambda(1) * cy[i] + lambda(2));
    if (v <= val[2]) continue;
    int k = 2;
    while (k > 0 && v > val[k - 1]) {
      val[k] = val[k - 1];
      best[k] = best[k - 1];
      --k;
    }
    val[k] = v;
    best[k] = static_cast<int>(i);
  }
  if (std::abs(triangleDet(cx, cy, best[0], best[1], best[2])) > 1e-3) return best;
  return frame.baseTriangle();
}

}  // namespace

SampleReport sampleL1(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0, std::span<double> w,
                      const L1Options& options) {
  const Index m = frame.size();
  assert(static_cast<Index>(w0.size()) == m && static_cast<Index>(w.size()) == m);
  const double* cx = frame.cx();
  const double* cy = frame.cy();
  SampleReport report;

  // r = b − A w0; the QEC multipliers λ = (AAᵀ)⁻¹ r come with it.
  const Eigen::Vector3d lambda = qecMultipliers(frame, xh, w0);
  const Eigen::Vector3d r = frame.aat() * lambda;

  std::array<int, 3> basis = startingBasis(frame, lambda);
  Eigen::Matrix3d inv;
  invertColumns(cx, cy, basis, inv);
  // Column signs σ make the basic values non-negative: x_B = σ ⊙ (A_B⁻¹ r).
  Eigen::Vector3d u = inv * r;
  Eigen::Vector3d sigma;
  for (int k = 0; k < 3; ++k) sigma(k) = u(k) < 0.0 ? -1.0 : 1.0;

  const double tol = options.tolerance;
  int degenerateRun = 0;
  bool optimal = false;
  int it = 0;
  for (;; ++it) {
    const Eigen::Vector3d xB = sigma.cwiseProduct(inv * r);
    const Eigen::Vector3d y = inv.transpose() * sigma;  // B⁻ᵀ 1 with B = A_B diag(σ)
    const bool bland = degenerateRun >= 8;
    // Pricing: the reduced cost of p_i is 1 − s_i, of q_i is 1 + s_i, with s_i = a_iᵀy. A
    // vectorized max |s_i| settles optimality (the common last pass); the index search follows
    // only when some column prices out.
    Index enter = -1;
    if (maxAbsAffine(cx, cy, m, y) > 1.0 + tol) {
      double enterScore = 1.0 + tol;
      for (Index i = 0; i < m; ++i) {
        const double s = std::abs(y(0) * cx[i] + y(1) * cy[i] + y(2));
        if (s > enterScore) {
          enter = i;
          if (bland) break;
          enterScore = s;
        }
      }
    }
    if (enter < 0) {
      optimal = xB.minCoeff() >= -tol;
      break;
    }
    if (it >= options.maxIterations) break;
    const double se = y(0) * cx[enter] + y(1) * cy[enter] + y(2);
    const double sign = se > 0.0 ? 1.0 : -1.0;
    const Eigen::Vector3d delta = sigma.cwiseProduct(inv * Eigen::Vector3d(cx[enter], cy[enter], 1.0)) * sign;
    // Ratio test; ties go to the largest pivot (Dantzig) or the lowest variable index (Bland).
    int leave = -1;
    double ratio = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (delta(k) <= 1e-12) continue;
      const double q = std::max(xB(k), 0.0) / delta(k);
      if (leave < 0 || q < ratio - 1e-15) {
        leave = k;
        ratio = q;
      } else if (q <= ratio + 1e-15) {
        const bool better = bland ? (2 * basis[k] + (sigma(k) < 0)) < (2 * basis[leave] + (sigma(leave) < 0))
                                  : delta(k) > delta(leave);
        if (better) {
          leave = k;
          ratio = std::min(ratio, q);
        }
      }
    }
    if (leave < 0) break;  // unbounded: impossible for a norm objective
    degenerateRun = ratio <= 1e-15 ? degenerateRun + 1 : 0;
    basis[static_cast<std::size_t>(leave)] = static_cast<int>(enter);
    sigma(leave) = sign;
    if (invertColumns(cx, cy, basis, inv) == 0.0) break;
  }
  report.iterations = it;

  if (optimal) {
    // v_B = A_B⁻¹ r with one step of iterative refinement (nearly flat triangles lose digits).
    Eigen::Matrix3d B;
    for (int k = 0; k < 3; ++k) B.col(k) = Eigen::Vector3d(cx[basis[k]], cy[basis[k]], 1.0);
    Eigen::Vector3d vB = inv * r;
    vB += inv * (r - B * vB);
    for (Index i = 0; i < m; ++i) w[i] = w0[i];
    for (int k = 0; k < 3; ++k) w[basis[k]] += vB(k);
    report.residual = (B * vB - r).lpNorm<Eigen::Infinity>();
    if (report.residual <= tol * (1.0 + r.lpNorm<Eigen::Infinity>())) return report;
  }
  sampleQec(frame, xh, w0, w);
  report.status = SolveStatus::NotConverged;
  report.residual = 0.0;
  return report;
}

}  // namespace kc
