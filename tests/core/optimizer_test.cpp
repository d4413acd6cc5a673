// WeightOptimizer: sample kinds, subsets, thread determinism, reports and input checks.
#include "kc/core/weights/optimizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "kc/core/parallel.h"

namespace kc {
namespace {

/// A hexagon cage in pixels, its edge midpoints (Edge), random interior samples and a few
/// exterior samples beyond the hull (Exterior); W0 positive, decaying with distance.
struct Scene {
  Points C;
  SampleSet S;
  Weights W0;
};

Scene makeScene(int interior = 400, int exterior = 20) {
  Scene s;
  const int m = 6;
  s.C.resize(m, 2);
  for (int i = 0; i < m; ++i)
    s.C.row(i) = Vec2(320 + 200 * std::cos(2 * M_PI * i / m), 240 + 180 * std::sin(2 * M_PI * i / m)).transpose();
  std::vector<Vec2> X;
  std::vector<SampleKind> kind;
  std::vector<std::array<int, 2>> edge;
  for (int i = 0; i < m; ++i) {
    X.emplace_back(s.C.row(i));
    kind.push_back(SampleKind::Control);
    edge.push_back({-1, -1});
  }
  for (int i = 0; i < m; ++i) {
    const int j = (i + 1) % m;
    X.push_back(0.3 * Vec2(s.C.row(i)) + 0.7 * Vec2(s.C.row(j)));
    kind.push_back(SampleKind::Edge);
    edge.push_back({i, j});
  }
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < interior; ++k) {
    X.emplace_back(320 + 100 * u(rng), 240 + 80 * u(rng));  // inside the hexagon
    kind.push_back(k % 7 == 0 ? SampleKind::Line : SampleKind::Interior);
    edge.push_back({-1, -1});
  }
  for (int k = 0; k < exterior; ++k) {
    const double a = 2 * M_PI * k / exterior;
    X.emplace_back(320 + 320 * std::cos(a), 240 + 300 * std::sin(a));
    kind.push_back(SampleKind::Exterior);
    edge.push_back({-1, -1});
  }
  const Index n = static_cast<Index>(X.size());
  s.S.X.resize(n, 2);
  s.S.edge.resize(n, 2);
  for (Index j = 0; j < n; ++j) {
    s.S.X.row(j) = X[static_cast<std::size_t>(j)].transpose();
    s.S.edge.row(j) << edge[static_cast<std::size_t>(j)][0], edge[static_cast<std::size_t>(j)][1];
  }
  s.S.kind = kind;
  s.W0.resize(n, m);
  for (Index j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i)
      s.W0(j, i) = std::exp(-(Vec2(s.S.X.row(j)) - Vec2(s.C.row(i))).squaredNorm() / (2 * 150.0 * 150.0));
  return s;
}

void expectReproduction(const Scene& s, const Weights& W, double tol) {
  for (Index j = 0; j < W.rows(); ++j) {
    EXPECT_NEAR(W.row(j).sum(), 1.0, tol) << "row " << j;
    // Reproduction relative to the cage's size (pixels): tol · 300 px.
    EXPECT_LE((W.row(j) * s.C - s.S.X.row(j)).lpNorm<Eigen::Infinity>(), tol * 300.0) << "row " << j;
  }
}

TEST(WeightOptimizer, AllMethodsKeepPartitionOfUnityAndReproduction) {
  const Scene s = makeScene();
  const WeightOptimizer opt(s.C);
  for (Method method : {Method::QP, Method::QEC, Method::L1}) {
    Weights W;
    const OptimizeReport r = opt.optimize(s.S, s.W0, W, OptimizeOptions{method});
    EXPECT_EQ(r.solved, s.S.size());
    EXPECT_EQ(r.failed, 0);
    EXPECT_EQ(r.infeasible, method == Method::QP ? 20 : 0);  // the exterior samples lie beyond the hull
    EXPECT_TRUE(W.allFinite());
    expectReproduction(s, W, 1e-12);
  }
}

TEST(WeightOptimizer, ControlAndEdgeSamplesGetLagrangeAndLinearWeights) {
  const Scene s = makeScene();
  const WeightOptimizer opt(s.C);
  for (Method method : {Method::QP, Method::QEC, Method::L1}) {
    Weights W;
    opt.optimize(s.S, s.W0, W, OptimizeOptions{method});
    for (int i = 0; i < 6; ++i) {
      Eigen::RowVectorXd e = Eigen::RowVectorXd::Zero(6);
      e(i) = 1.0;
      EXPECT_EQ(W.row(i), e);
      const Index j = 6 + i;
      Eigen::RowVectorXd lin = Eigen::RowVectorXd::Zero(6);
      lin(i) = 0.3;
      lin((i + 1) % 6) = 0.7;
      EXPECT_LE((W.row(j) - lin).lpNorm<Eigen::Infinity>(), 1e-14);
    }
  }
}

TEST(WeightOptimizer, QpWeightsAreNonNegativeInsideTheHull) {
  const Scene s = makeScene();
  const WeightOptimizer opt(s.C);
  Weights W;
  opt.optimize(s.S, s.W0, W, OptimizeOptions{Method::QP});
  const Index interiorEnd = s.S.size() - 20;
  EXPECT_GE(W.topRows(interiorEnd).minCoeff(), 0.0);
  EXPECT_LT(W.bottomRows(20).minCoeff(), 0.0);  // exterior: the fallback's shifted bound −t
}

TEST(WeightOptimizer, SubsetTouchesOnlyItsRows) {
  const Scene s = makeScene();
  const WeightOptimizer opt(s.C);
  Weights full;
  opt.optimize(s.S, s.W0, full, OptimizeOptions{Method::QP});
  Weights W = Weights::Constant(s.S.size(), 6, -7.0);
  const std::vector<Index> subset = {3, 8, 40, 41, 200, s.S.size() - 1};
  const OptimizeReport r = opt.optimize(s.S, s.W0, W, OptimizeOptions{Method::QP}, subset);
  EXPECT_EQ(r.solved, 6);
  EXPECT_EQ(r.infeasible, 1);
  for (Index j = 0; j < s.S.size(); ++j) {
    if (std::find(subset.begin(), subset.end(), j) != subset.end()) {
      EXPECT_EQ(W.row(j), full.row(j)) << j;
    } else {
      EXPECT_TRUE((W.row(j).array() == -7.0).all()) << j;
    }
  }
}

TEST(WeightOptimizer, BitIdenticalForOneAndTwoThreads) {
  const Scene s = makeScene(3000, 50);
  const WeightOptimizer opt(s.C);
  for (Method method : {Method::QP, Method::QEC, Method::L1}) {
    Weights W1, W2;
    OptimizeReport r1, r2;
    {
      ScopedThreadCount one(1);
      r1 = opt.optimize(s.S, s.W0, W1, OptimizeOptions{method});
    }
    {
      ScopedThreadCount two(2);
      r2 = opt.optimize(s.S, s.W0, W2, OptimizeOptions{method});
    }
    EXPECT_TRUE((W1.array() == W2.array()).all());
    EXPECT_EQ(r1.infeasible, r2.infeasible);
    EXPECT_EQ(r1.maxIterations, r2.maxIterations);
  }
}

TEST(WeightOptimizer, RejectsBadInput) {
  const Scene s = makeScene(10, 0);
  Points line(3, 2);
  line << 0, 0, 1, 1, 2, 2;
  EXPECT_THROW(WeightOptimizer{line}, std::invalid_argument);
  EXPECT_THROW(WeightOptimizer{Points(2, 2)}, std::invalid_argument);
  const WeightOptimizer opt(s.C);
  Weights W;
  Weights bad = s.W0;
  bad(15, 2) = std::nan("");
  EXPECT_THROW(opt.optimize(s.S, bad, W, {}), std::invalid_argument);
  EXPECT_THROW(opt.optimize(s.S, s.W0.leftCols(5), W, {}), std::invalid_argument);
  const std::vector<Index> outOfRange = {s.S.size()};
  W = s.W0;
  EXPECT_THROW(opt.optimize(s.S, s.W0, W, {}, outOfRange), std::invalid_argument);
  const std::vector<Index> ok = {7};
  Weights wrongShape(3, 6);
  EXPECT_THROW(opt.optimize(s.S, s.W0, wrongShape, {}, ok), std::invalid_argument);
  EXPECT_THROW(WeightOptimizer{}.optimize(s.S, s.W0, W, {}), std::invalid_argument);
}

TEST(WeightOptimizer, ReportsIterations) {
  const Scene s = makeScene();
  const WeightOptimizer opt(s.C);
  Weights W;
  const OptimizeReport qp = opt.optimize(s.S, s.W0, W, OptimizeOptions{Method::QP});
  EXPECT_GT(qp.maxIterations, 0);
  EXPECT_LT(qp.maxIterations, 30);
  const OptimizeReport qec = opt.optimize(s.S, s.W0, W, OptimizeOptions{Method::QEC});
  EXPECT_EQ(qec.maxIterations, 0);
}

}  // namespace
}  // namespace kc
