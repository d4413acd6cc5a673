// The thesis's grid experiment (section 4.7, Figure 4.1): 101×101 grid at spacing T = 0.1,
// four controls at the corners, targets by inverse squared distance (4.10) with p = 1.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <iostream>

#include "kc/core/weights/optimizer.h"
#include "lp_reference.h"

namespace kc {
namespace {

constexpr int kN = 101;
constexpr double kT = 0.1;
constexpr double kSide = (kN - 1) * kT;  // 10

struct Grid {
  Points C;
  SampleSet S;
  Weights W0;
};

/// Samples: the 4 corner controls (3.18), then every other grid point as Interior — the thesis's
/// rows (b), (c) and (e) of Figure 4.1 optimize all points, boundary included.
Grid makeGrid() {
  Grid g;
  g.C.resize(4, 2);
  g.C << 0, 0, kSide, 0, kSide, kSide, 0, kSide;
  const Index n = kN * kN;
  g.S.X.resize(n, 2);
  g.S.kind.assign(static_cast<std::size_t>(n), SampleKind::Interior);
  g.S.edge.setConstant(n, 2, -1);
  for (int i = 0; i < 4; ++i) {
    g.S.X.row(i) = g.C.row(i);
    g.S.kind[static_cast<std::size_t>(i)] = SampleKind::Control;
  }
  Index j = 4;
  for (int a = 0; a < kN; ++a)
    for (int b = 0; b < kN; ++b) {
      const bool corner = (a == 0 || a == kN - 1) && (b == 0 || b == kN - 1);
      if (!corner) g.S.X.row(j++) = Vec2(a * kT, b * kT).transpose();
    }
  // (4.10) computed directly: w_ij = 1 / (1 + (|x_j − c_i| / p)²), p = 1.
  const double p = 1.0;
  g.W0.resize(n, 4);
  for (Index s = 0; s < n; ++s)
    for (int i = 0; i < 4; ++i) {
      const double d = (Vec2(g.S.X.row(s)) - Vec2(g.C.row(i))).norm();
      g.W0(s, i) = 1.0 / (1.0 + (d / p) * (d / p));
    }
  return g;
}

Weights run(const Grid& g, Method method, OptimizeReport* report = nullptr) {
  const WeightOptimizer opt(g.C);
  Weights W;
  const OptimizeReport r = opt.optimize(g.S, g.W0, W, OptimizeOptions{method});
  EXPECT_EQ(r.failed, 0);
  EXPECT_EQ(r.infeasible, 0);  // the whole grid is the hull (boundary included)
  EXPECT_EQ(r.solved, kN * kN);
  if (report) *report = r;
  return W;
}

void expectPartitionAndReproduction(const Grid& g, const Weights& W) {
  double pu = 0.0, rep = 0.0;
  for (Index s = 0; s < W.rows(); ++s) {
    pu = std::max(pu, std::abs(W.row(s).sum() - 1.0));
    rep = std::max(rep, (W.row(s) * g.C - g.S.X.row(s)).lpNorm<Eigen::Infinity>());
  }
  EXPECT_LE(pu, 1e-12);
  EXPECT_LE(rep, 1e-12);
}

TEST(GridExperiment, QpWeightsAreNonNegativeEverywhere) {
  const Grid g = makeGrid();
  OptimizeReport r;
  const Weights W = run(g, Method::QP, &r);
  EXPECT_GE(W.minCoeff(), 0.0);  // exact: no tolerance
  expectPartitionAndReproduction(g, W);
  std::cout << "QP: max Newton iterations " << r.maxIterations << ", " << r.seconds * 1e3 << " ms\n";
}

/// Reference QEC weights (4.2–4.6) by a dense solve of the KKT system [I Aᵀ; A 0] in the grid's
/// own coordinates (no normalization, no closed form): w = argmin |w − w0|² s.t. Cᵀw = x, 1ᵀw = 1.
Eigen::VectorXd qecReference(const Grid& g, Index s) {
  Eigen::Matrix<double, 7, 7> K = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Matrix<double, 7, 1> rhs;
  K.topLeftCorner<4, 4>().setIdentity();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d a(g.C(i, 0), g.C(i, 1), 1.0);
    K.block<1, 3>(i, 4) = a.transpose();
    K.block<3, 1>(4, i) = a;
    rhs(i) = g.W0(s, i);
  }
  rhs.tail<3>() = Eigen::Vector3d(g.S.X(s, 0), g.S.X(s, 1), 1.0);
  return K.fullPivLu().solve(rhs).head<4>();
}

TEST(GridExperiment, QecWeightsAreNegativeNearTheOppositeCorner) {
  const Grid g = makeGrid();
  const Weights W = run(g, Method::QEC);
  expectPartitionAndReproduction(g, W);
  Weights ref(W.rows(), 4);
  for (Index s = 4; s < W.rows(); ++s) ref.row(s) = qecReference(g, s).transpose();
  EXPECT_LE((W.bottomRows(W.rows() - 4) - ref.bottomRows(W.rows() - 4)).lpNorm<Eigen::Infinity>(), 1e-12);
  for (int i = 0; i < 4; ++i) {
    const Vec2 c(g.C.row(i));
    const Vec2 opposite = Vec2::Constant(kSide) - c;
    Index argmin = 4;
    double farthest = 0.0;
    for (Index s = 4; s < W.rows(); ++s) {
      if (W(s, i) < W(argmin, i)) argmin = s;
      if (W(s, i) < 0.0) farthest = std::max(farthest, (Vec2(g.S.X.row(s)) - opposite).norm());
    }
    // Figure 4.1 (b): the weight of a corner goes negative, and only in the neighbourhood of the
    // opposite corner: the most negative weight lies in the opposite corner's quadrant and every
    // negative weight is nearer the opposite corner than its own control.
    EXPECT_LT(W(argmin, i), 0.0) << "control " << i;
    const Vec2 at(g.S.X.row(argmin));
    EXPECT_LT((at - opposite).lpNorm<Eigen::Infinity>(), 0.5 * kSide) << "control " << i;
    EXPECT_LT(farthest, 0.5 * (opposite - c).norm()) << "control " << i;
    std::cout << "QEC control " << i << ": min weight " << W(argmin, i) << " at distance "
              << (Vec2(g.S.X.row(argmin)) - opposite).norm() << " from the opposite corner; negatives within "
              << farthest << "\n";
  }
}

TEST(GridExperiment, L1WeightsAreOptimal) {
  const Grid g = makeGrid();
  OptimizeReport r;
  const Weights W = run(g, Method::L1, &r);
  expectPartitionAndReproduction(g, W);
  // The ℓ1 optimum (4.8) is often not unique (an LP face), so the reference is its value: GLPK's
  // exact simplex on every tenth sample.
  for (Index s = 4; s < W.rows(); s += 10) {
    const test::Problem p{g.C, Vec2(g.S.X.row(s)), g.W0.row(s).transpose()};
    Eigen::VectorXd v;
    double objective = 0.0;
    ASSERT_TRUE(test::glpkSolve(p, v, objective)) << "sample " << s;
    EXPECT_NEAR((W.row(s) - g.W0.row(s)).lpNorm<1>(), objective, 1e-9 * (1.0 + objective)) << "sample " << s;
  }
  double minInterior = 0.0, minBoundary = 0.0;
  Index negatives = 0;
  for (Index s = 4; s < W.rows(); ++s) {
    const Vec2 x(g.S.X.row(s));
    const bool boundary = x.x() == 0.0 || x.y() == 0.0 || x.x() == kSide || x.y() == kSide;
    const double low = W.row(s).minCoeff();
    (boundary ? minBoundary : minInterior) = std::min(boundary ? minBoundary : minInterior, low);
    negatives += (W.row(s).array() < 0.0).count();
  }
  std::cout << "L1: min weight " << minInterior << " inside, " << minBoundary << " on the grid boundary; "
            << negatives << " negative entries of " << W.size() << "; max pivots " << r.maxIterations << "\n";
}

TEST(GridExperiment, EdgeSamplesGiveLinearPrecisionForQec) {
  // Figure 4.1 row (d): QEC with the boundary samples marked as edges gets linear weights there.
  Grid g = makeGrid();
  for (Index s = 4; s < g.S.size(); ++s) {
    const Vec2 x(g.S.X.row(s));
    int k = -1, l = -1;
    if (x.y() == 0.0) k = 0, l = 1;
    else if (x.x() == kSide) k = 1, l = 2;
    else if (x.y() == kSide) k = 2, l = 3;
    else if (x.x() == 0.0) k = 3, l = 0;
    if (k < 0) continue;
    g.S.kind[static_cast<std::size_t>(s)] = SampleKind::Edge;
    g.S.edge.row(s) << k, l;
  }
  const Weights W = run(g, Method::QEC);
  expectPartitionAndReproduction(g, W);
  for (Index s = 4; s < g.S.size(); ++s) {
    if (g.S.kind[static_cast<std::size_t>(s)] != SampleKind::Edge) continue;
    const int k = g.S.edge(s, 0), l = g.S.edge(s, 1);
    for (int i = 0; i < 4; ++i) {
      if (i != k && i != l) {
        EXPECT_EQ(W(s, i), 0.0);
      }
    }
    EXPECT_GE(W(s, k), 0.0);
    EXPECT_GE(W(s, l), 0.0);
  }
}

}  // namespace
}  // namespace kc
