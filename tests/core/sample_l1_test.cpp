// Per-sample ℓ1 optimization (thesis 4.8) against GLPK on random and degenerate problems.
#include "kc/core/weights/sample_l1.h"

#include <gtest/gtest.h>

#include "lp_reference.h"
#include "sample_problems.h"

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>
#include "random_point.h"

namespace kc {
namespace {

using test::glpkSolve;
using test::Problem;
using test::randomControls;

Eigen::VectorXd solve(const Problem& p, SampleReport* report = nullptr) {
  return test::solveSample(sampleL1, p, report);
}

/// Objective always matches GLPK's to 1e-8 (relative to 1 + objective); the solution too (relative
/// to 1 + |v|∞) when GLPK finds the optimal face to be a single point (min and max of a random
/// direction over it agree). Returns whether the optimum was unique.
bool expectMatchesGlpk(const Problem& p, const std::string& what, std::mt19937& rng) {
  SampleReport report;
  const Eigen::VectorXd w = solve(p, &report);
  EXPECT_EQ(report.status, SolveStatus::Ok) << what;
  EXPECT_NEAR(w.sum(), 1.0, 1e-12) << what;
  EXPECT_LE((p.C.transpose() * w - p.x).lpNorm<Eigen::Infinity>(), 1e-12) << what;
  Eigen::VectorXd v;
  double objective = 0.0;
  EXPECT_TRUE(glpkSolve(p, v, objective)) << what;
  const double ours = (w - p.w0).lpNorm<1>();
  EXPECT_NEAR(ours, objective, 1e-8 * (1.0 + objective)) << what;
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::VectorXd dir(p.C.rows());
  for (Index i = 0; i < dir.size(); ++i) dir(i) = n(rng);
  Eigen::VectorXd vMin, vMax;
  double oMin = 0.0, oMax = 0.0;
  const Eigen::VectorXd neg = -dir;
  if (!glpkSolve(p, vMin, oMin, &dir, objective + 1e-10) || !glpkSolve(p, vMax, oMax, &neg, objective + 1e-10))
    return false;
  const double scale = 1.0 + v.lpNorm<Eigen::Infinity>();
  if ((vMin - vMax).lpNorm<Eigen::Infinity>() > 1e-6 * scale) return false;
  EXPECT_LE((w - p.w0 - v).lpNorm<Eigen::Infinity>(), 1e-8 * scale) << what << "\nv   = " << (w - p.w0).transpose()
                                                          << "\nref = " << v.transpose();
  return true;
}

TEST(SampleL1Slow, MatchesGlpkOnRandomProblems) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int unique = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int m = 3 + trial % 38;
    Problem p{randomControls(rng, m), 1.2 * (2.0 * test::randomPoint(u, rng) - Vec2::Ones()), Eigen::VectorXd(m)};
    for (int i = 0; i < m; ++i) p.w0(i) = trial % 2 == 0 ? 2.0 * u(rng) - 1.0 : u(rng) / m;
    unique += expectMatchesGlpk(p, "trial " + std::to_string(trial), rng);
  }
  // Not all optima are unique: whenever some v ≥ 0 (or ≤ 0) is feasible, every such v has
  // |v|₁ = |1 − 1ᵀw0|, the lower bound, so the optimal face is a polytope. About 2/3 are unique.
  EXPECT_GE(unique, 200);
}

/// `trials` degenerate problems (x at a control, on a segment between two, or anywhere; many zero
/// targets; every third already feasible), m = 3..40 controls, each checked against GLPK.
void expectMatchesGlpkOnDegenerateProblems(int trials) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < trials; ++trial) {
    const int m = 3 + trial % 38;
    Problem p{randomControls(rng, m), Vec2::Zero(), Eigen::VectorXd::Zero(m)};
    const int k = trial % m, l = (trial + 1) % m;
    switch (trial % 4) {
      case 0: p.x = Vec2(p.C.row(k)); break;  // at a control point
      case 1: {
        const double a = u(rng);  // on a segment between two controls
        p.x = a * Vec2(p.C.row(k)) + (1.0 - a) * Vec2(p.C.row(l));
        break;
      }
      default: p.x = 2.0 * test::randomPoint(u, rng) - Vec2::Ones(); break;
    }
    // Many zeros; every third problem already feasible (w0 = e_k at x = c_k: v = 0).
    for (int i = 0; i < m; ++i) p.w0(i) = u(rng) < 0.7 ? 0.0 : u(rng);
    if (trial % 3 == 0) {
      p.w0.setZero();
      p.w0(k) = 1.0;
      p.x = Vec2(p.C.row(k));
    }
    expectMatchesGlpk(p, "trial " + std::to_string(trial), rng);
  }
}

// 48 trials: every combination of the placement (trial mod 4) and the feasible case (mod 3) 4 times.
TEST(SampleL1, MatchesGlpkOnDegenerateProblems) { expectMatchesGlpkOnDegenerateProblems(48); }

TEST(SampleL1Slow, MatchesGlpkOnMoreDegenerateProblems) { expectMatchesGlpkOnDegenerateProblems(200); }

TEST(SampleL1, FeasibleTargetIsReturnedUnchanged) {
  std::mt19937 rng(8);
  const Points C = randomControls(rng, 15);
  Eigen::VectorXd w0 = Eigen::VectorXd::Random(15);
  w0 /= w0.sum();
  const Problem p{C, C.transpose() * w0, w0};
  const Eigen::VectorXd w = solve(p);
  EXPECT_LE((w - w0).lpNorm<Eigen::Infinity>(), 1e-14);
}

TEST(SampleL1, DifferenceIsSparse) {
  // A basic optimal solution changes at most three weights (3 equality constraints).
  std::mt19937 rng(77);
  for (int trial = 0; trial < 50; ++trial) {
    const Points C = randomControls(rng, 20);
    const Problem p{C, Vec2(0.1, -0.2), Eigen::VectorXd::Random(20).cwiseAbs() / 20.0};
    const Eigen::VectorXd v = solve(p) - p.w0;
    EXPECT_LE((v.array().abs() > 0.0).count(), 3);
  }
}

}  // namespace
}  // namespace kc
