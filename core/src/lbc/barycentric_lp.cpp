#include "barycentric_lp.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "kc/core/cage.h"

namespace kc::detail {
namespace {

/// Barycentric coordinates of x in the triangle of controls b; false for a degenerate triangle.
bool barycentric(const Points& C, const std::array<int, 3>& b, const Vec2& x, Eigen::Vector3d& l) {
  const Vec2 c0 = C.row(b[0]), e1 = Vec2(C.row(b[1])) - c0, e2 = Vec2(C.row(b[2])) - c0, p = x - c0;
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  const double scale = e1.squaredNorm() * e2.squaredNorm();
  if (!(det * det > 1e-24 * scale)) return false;
  l(1) = (p.x() * e2.y() - p.y() * e2.x()) / det;
  l(2) = (e1.x() * p.y() - e1.y() * p.x()) / det;
  l(0) = 1.0 - l(1) - l(2);
  return true;
}

}  // namespace

BarycentricLp::BarycentricLp(const Points& C) : m_C(C) {
  const std::vector<int> hull = convexHull(C);
  for (std::size_t k = 1; k + 1 < hull.size(); ++k) m_fan.push_back({hull[0], hull[k], hull[k + 1]});
}

double BarycentricLp::lowerBound(const Vec2& x, const double* q, std::array<int, 3>& basis) const {
  const Index m = m_C.rows();
  constexpr double kInside = -1e-12;
  Eigen::Vector3d l;
  const bool warm = basis[0] >= 0 && barycentric(m_C, basis, x, l) && l.minCoeff() >= kInside;
  if (!warm) {  // the fan triangle that contains x best
    double best = -std::numeric_limits<double>::infinity();
    for (const auto& t : m_fan)
      if (barycentric(m_C, t, x, l) && l.minCoeff() > best) {
        best = l.minCoeff();
        basis = t;
      }
    if (!(best >= kInside)) return -std::numeric_limits<double>::infinity();
  }
  double qScale = 0.0;
  for (Index j = 0; j < m; ++j) qScale = std::max(qScale, std::abs(q[j]));
  const int maxPivots = int(4 * m);
  double bound = -std::numeric_limits<double>::infinity();
  for (int pivot = 0;; ++pivot) {
    // λ: λ·(c_j, 1) = q_j on the basis; then the reduced costs and the bound they give.
    Eigen::Matrix3d A;
    for (int k = 0; k < 3; ++k) A.row(k) << m_C(basis[std::size_t(k)], 0), m_C(basis[std::size_t(k)], 1), 1.0;
    const Eigen::PartialPivLU<Eigen::Matrix3d> lu(A);
    const Eigen::Vector3d lambda = lu.solve(Eigen::Vector3d(q[basis[0]], q[basis[1]], q[basis[2]]));
    if (!lambda.allFinite()) break;
    double minReduced = 0.0;
    int entering = -1;
    for (Index j = 0; j < m; ++j) {
      const double r = q[j] - (lambda(0) * m_C(j, 0) + lambda(1) * m_C(j, 1) + lambda(2));
      // Most negative first (Dantzig); past half the cap the first negative (Bland: no cycling).
      if (r < minReduced) {
        minReduced = r;
        if (entering < 0 || pivot < maxPivots / 2) entering = int(j);
      }
    }
    bound = std::max(bound, lambda(0) * x.x() + lambda(1) * x.y() + lambda(2) + minReduced);
    if (entering < 0 || minReduced >= -1e-14 * qScale || pivot == maxPivots) break;
    // Ratio test: moving weight to the entering control along its barycentric coordinates d in
    // the basis triangle; the basis control whose weight reaches 0 first leaves.
    Eigen::Vector3d d;
    if (!barycentric(m_C, basis, Vec2(m_C.row(entering)), d) || !barycentric(m_C, basis, x, l)) break;
    int leaving = -1;
    double ratio = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k)
      if (d(k) > 1e-12 && std::max(0.0, l(k)) / d(k) < ratio) {
        ratio = std::max(0.0, l(k)) / d(k);
        leaving = k;
      }
    if (leaving < 0) break;
    basis[std::size_t(leaving)] = entering;
  }
  return bound;
}

}  // namespace kc::detail
