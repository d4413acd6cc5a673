#pragma once
// Test support for the per-sample solvers: random problems and a one-call solve.

#include <Eigen/Core>
#include <random>

#include "kc/core/weights/sample_qec.h"
#include "kc/core/weights/sample_qp.h"
#include "random_point.h"

namespace kc::test {

/// One per-sample problem: controls C (m×2), the sample x, the targets w0.
struct Problem {
  Points C;
  Vec2 x;
  Eigen::VectorXd w0;
};

/// m control points uniform in offset + scale·[−1, 1]².
inline Points randomControls(std::mt19937& rng, int m, double scale = 1.0, const Vec2& offset = Vec2::Zero()) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Points C(m, 2);
  for (int i = 0; i < m; ++i) C.row(i) = (offset + scale * test::randomPoint(u, rng)).transpose();
  return C;
}

/// A random convex combination of the control points (strictly inside the hull).
inline Vec2 randomInside(std::mt19937& rng, const Points& C) {
  std::exponential_distribution<double> e(1.0);
  Eigen::VectorXd a(C.rows());
  for (Index i = 0; i < C.rows(); ++i) a(i) = e(rng);
  a /= a.sum();
  return C.transpose() * a;
}

/// w = solver(frame, x̂, w0) for a per-sample solver with sampleQp's signature (sampleQp, sampleL1).
template <class Solver>
Eigen::VectorXd solveSample(Solver solver, const Problem& p, SampleReport* report = nullptr) {
  const ControlFrame frame(p.C);
  Eigen::VectorXd w(p.C.rows());
  const SampleReport r = solver(frame, frame.normalize(p.x), {p.w0.data(), static_cast<std::size_t>(p.w0.size())},
                                {w.data(), static_cast<std::size_t>(w.size())}, {});
  if (report) *report = r;
  return w;
}

}  // namespace kc::test
