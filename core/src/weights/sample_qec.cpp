#include "kc/core/weights/sample_qec.h"

#include "simd2.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "kc/core/cage.h"

namespace kc {
using detail::D2;
using detail::load2;
using detail::store2;

ControlFrame::ControlFrame(const Points& C) {
  const Index m = C.rows();
  if (m < 3) throw std::invalid_argument("weights: need at least 3 control points, got " + std::to_string(m));
  if (!C.allFinite()) throw std::invalid_argument("weights: non-finite control point coordinate");
  m_m = m;
  m_center = C.colwise().mean().transpose();
  double sq = 0.0;
  for (Index i = 0; i < m; ++i) sq += (Vec2(C.row(i)) - m_center).squaredNorm();
  m_scale = std::sqrt(sq / static_cast<double>(m));
  if (!(m_scale > 0.0)) throw std::invalid_argument("weights: all control points coincide");
  m_cx.resize(static_cast<std::size_t>(m));
  m_cy.resize(static_cast<std::size_t>(m));
  Eigen::Matrix3d aat = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < m; ++i) {
    const Vec2 c = normalize(Vec2(C.row(i)));
    m_cx[static_cast<std::size_t>(i)] = c.x();
    m_cy[static_cast<std::size_t>(i)] = c.y();
    m_cxx.push_back(c.x() * c.x());
    m_cxy.push_back(c.x() * c.y());
    m_cyy.push_back(c.y() * c.y());
    const Eigen::Vector3d a(c.x(), c.y(), 1.0);
    aat += a * a.transpose();
  }
  // Normalized: aat = diag-ish with trace m·2 + m; collinear points make it singular.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(aat);
  if (eig.eigenvalues()(0) <= 1e-10 * eig.eigenvalues()(2))
    throw std::invalid_argument("weights: the control points are collinear (no 2D reproduction possible)");
  m_aat = aat;
  m_aatInv = aat.inverse();

  // Hull half-planes in normalized coordinates; orientation fixed by the signed area.
  const std::vector<int> hull = convexHull(C);
  const std::size_t h = hull.size();
  double area = 0.0;
  for (std::size_t k = 0; k < h; ++k) {
    const std::size_t k1 = (k + 1) % h;
    area += m_cx[hull[k]] * m_cy[hull[k1]] - m_cx[hull[k1]] * m_cy[hull[k]];
  }
  const double orient = area > 0.0 ? 1.0 : -1.0;
  for (std::size_t k = 0; k < h; ++k) {
    const std::size_t k1 = (k + 1) % h;
    const Vec2 p(m_cx[hull[k]], m_cy[hull[k]]), q(m_cx[hull[k1]], m_cy[hull[k1]]);
    const Vec2 e = q - p;
    if (e.norm() == 0.0) continue;
    // For a counter-clockwise polygon the outward normal of edge e is (e_y, −e_x).
    const Vec2 n = orient * Vec2(e.y(), -e.x()) / e.norm();
    m_hullNormal.push_back(n);
    m_hullOffset.push_back(n.dot(p));
  }

  // A large triangle: the hull vertex farthest from the centroid, the one farthest from it, and
  // the one farthest from the line through both.
  auto at = [&](int i) { return Vec2(m_cx[static_cast<std::size_t>(i)], m_cy[static_cast<std::size_t>(i)]); };
  int i0 = hull[0], i1 = hull[0], i2 = hull[0];
  for (int i : hull)
    if (at(i).squaredNorm() > at(i0).squaredNorm()) i0 = i;
  for (int i : hull)
    if ((at(i) - at(i0)).squaredNorm() > (at(i1) - at(i0)).squaredNorm()) i1 = i;
  const Vec2 e = at(i1) - at(i0);
  double best = -1.0;
  for (int i : hull) {
    const Vec2 f = at(i) - at(i0);
    const double a = std::abs(e.x() * f.y() - e.y() * f.x());
    if (a > best) {
      best = a;
      i2 = i;
    }
  }
  m_baseTriangle = {i0, i1, i2};
}

double ControlFrame::hullExcess(const Vec2& xh) const {
  double worst = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < m_hullNormal.size(); ++k) worst = std::max(worst, m_hullNormal[k].dot(xh) - m_hullOffset[k]);
  return worst;
}

double ControlFrame::hullShrink(const Vec2& xh) const {
  // β x̂ is inside edge k iff β n·x̂ ≤ n·p, and n·p > 0 because the centroid is interior.
  double beta = 1.0;
  for (std::size_t k = 0; k < m_hullNormal.size(); ++k) {
    const double nx = m_hullNormal[k].dot(xh);
    if (nx > m_hullOffset[k]) beta = std::min(beta, m_hullOffset[k] / nx);
  }
  return beta;
}


Eigen::Vector3d qecMultipliers(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0) {
  const Index m = frame.size();
  assert(static_cast<Index>(w0.size()) == m);
  const double* cx = frame.cx();
  const double* cy = frame.cy();
  const double* v = w0.data();
  // r = A w0.
  D2 rx = {0.0, 0.0}, ry = rx, r1 = rx;
  Index i = 0;
  for (; i + 1 < m; i += 2) {
    const D2 w = load2(v + i);
    rx += w * load2(cx + i);
    ry += w * load2(cy + i);
    r1 += w;
  }
  double sx = rx[0] + rx[1], sy = ry[0] + ry[1], s1 = r1[0] + r1[1];
  if (i < m) {
    sx += v[i] * cx[i];
    sy += v[i] * cy[i];
    s1 += v[i];
  }
  return frame.aatInv() * Eigen::Vector3d(xh.x() - sx, xh.y() - sy, 1.0 - s1);
}

Eigen::Vector3d sampleQec(const ControlFrame& frame, const Vec2& xh, std::span<const double> w0,
                          std::span<double> w) {
  const Index m = frame.size();
  assert(static_cast<Index>(w.size()) == m);
  const double* cx = frame.cx();
  const double* cy = frame.cy();
  const Eigen::Vector3d lambda = qecMultipliers(frame, xh, w0);
  const double l0 = lambda(0), l1 = lambda(1), l2 = lambda(2);
  const D2 L0 = {l0, l0}, L1 = {l1, l1}, L2 = {l2, l2};
  Index j = 0;
  for (; j + 1 < m; j += 2) store2(w.data() + j, load2(w0.data() + j) + (L0 * load2(cx + j) + L1 * load2(cy + j) + L2));
  if (j < m) w[j] = w0[j] + (l0 * cx[j] + l1 * cy[j] + l2);
  return lambda;
}

void edgeWeights(const Points& C, int k, int l, const Vec2& x, std::span<double> w) {
  std::fill(w.begin(), w.end(), 0.0);
  const Vec2 ck(C.row(k)), cl(C.row(l));
  const Vec2 e = ck - cl;
  const double wk = (x - cl).dot(e) / e.squaredNorm();
  w[static_cast<std::size_t>(k)] = wk;
  w[static_cast<std::size_t>(l)] = 1.0 - wk;
}

}  // namespace kc
