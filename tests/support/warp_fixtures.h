#pragma once
// Test support for the warp mesh and the outside modes: mean value coordinates (an independent,
// closed-form coordinate field), the edge data at the nearest cage point (a field for cages with
// sticks) and a small non-convex cage.

#include <algorithm>
#include <cmath>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc {

/// Mean value coordinates (Floater 2003) of the closed polygon C at the rows of X: partition of
/// unity and linear reproduction everywhere off the boundary; linear on the edges.
inline Weights meanValueWeights(const Points& C, const Points& X) {
  const Index m = C.rows();
  Weights W = Weights::Zero(X.rows(), m);
  for (Index p = 0; p < X.rows(); ++p) {
    const Points S = C.rowwise() - X.row(p);  // s_i = c_i − x
    const Eigen::VectorXd r = S.rowwise().norm();
    Eigen::VectorXd t = Eigen::VectorXd::Zero(m);  // tan(α_i / 2) for the angle at x of edge i
    bool done = false;
    for (Index i = 0; i < m && !done; ++i)
      if (r(i) < 1e-12) W(p, i) = 1.0, done = true;
    for (Index i = 0; i < m && !done; ++i) {
      const Index j = (i + 1) % m;
      const double A = 0.5 * (S(i, 0) * S(j, 1) - S(i, 1) * S(j, 0)), D = S.row(i).dot(S.row(j));
      if (std::abs(A) < 1e-12 * r(i) * r(j)) {
        if (D < 0) {  // on the edge: linear interpolation
          W(p, i) = r(j) / (r(i) + r(j));
          W(p, j) = r(i) / (r(i) + r(j));
          done = true;
        }
      } else {
        t(i) = (r(i) * r(j) - D) / (2 * A);
      }
    }
    if (done) continue;
    for (Index i = 0; i < m; ++i) W(p, i) = (t((i + m - 1) % m) + t(i)) / r(i);
    W.row(p) /= W.row(p).sum();
  }
  return W;
}

/// A non-convex 8-point "L"-ish cage inside a 120×100 image.
inline Cage lCage() {
  Points C(8, 2);
  C << 15, 10, 70, 12, 72, 45, 105, 48, 108, 90, 40, 92, 12, 88, 30, 50;
  return Cage::polygon(C);
}

/// λ_i at the cage point closest to p (the piecewise-linear edge data: 1 at a control point,
/// linear along its edges), #m: a field with partition of unity and values in [0, 1] for any
/// cage, sticks included.
inline Eigen::VectorXd edgeDataAt(const Cage& cage, const Vec2& p) {
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(cage.size());
  double best = 1e300;
  for (const auto& [a, b] : cageEdges(cage)) {
    const Vec2 A = cage.C.row(a), d = Vec2(cage.C.row(b)) - A;
    const double s = std::clamp((p - A).dot(d) / d.squaredNorm(), 0.0, 1.0);
    if (const double dist = (A + s * d - p).norm(); dist < best) {
      best = dist;
      lambda.setZero();
      lambda(a) = 1 - s;
      lambda(b) = s;
    }
  }
  return lambda;
}

/// A bent open stick of three points (no interior).
inline Cage bentStick() {
  Cage stick;
  stick.C.resize(3, 2);
  stick.C << 20, 30, 60, 50, 100, 40;
  stick.closed = false;
  stick.edges = {{0, 1}, {1, 2}};
  validateCage(stick);
  return stick;
}

}  // namespace kc
