#include "kc/core/lbc/lbc_solver.h"

#include <gtest/gtest.h>

#include <cstring>

#include "kc/core/parallel.h"
#include "lbc_cages.h"

namespace kc {
namespace {

CageMesh starMesh(double h = 14.0) {
  CageMeshOptions options;
  options.spacing = h;
  return meshCageInterior(test::starCage(), options);
}

/// max over vertices of |Σ w − 1| and |Σ w c − v| (pixels).
std::pair<double, double> affineErrors(const CageMesh& mesh, const Weights& W) {
  const Points C = mesh.V.topRows(mesh.controls);
  double pu = 0.0, rep = 0.0;
  for (Index v = 0; v < mesh.size(); ++v) {
    pu = std::max(pu, std::abs(W.row(v).sum() - 1.0));
    rep = std::max(rep, (W.row(v) * C - mesh.V.row(v)).norm());
  }
  return {pu, rep};
}

TEST(LbcSolver, BarycentricNonNegativeLagrangeAndLinearOnEdges) {
  const CageMesh mesh = starMesh();
  const LbcResult r = solveLbc(mesh);
  ASSERT_EQ(r.report.status, SolveStatus::Ok);
  ASSERT_EQ(r.W.rows(), mesh.size());
  ASSERT_EQ(r.W.cols(), mesh.controls);
  const auto [pu, rep] = affineErrors(mesh, r.W);
  EXPECT_LE(pu, 1e-9);
  EXPECT_LE(rep, 1e-9);
  EXPECT_GE(r.W.minCoeff(), 0.0);
  EXPECT_EQ(r.report.projectionFailures, 0);
  for (Index i = 0; i < mesh.controls; ++i)
    for (Index j = 0; j < mesh.controls; ++j) EXPECT_EQ(r.W(i, j), i == j ? 1.0 : 0.0);
  for (Index v = mesh.controls; v < mesh.boundary; ++v) {
    Eigen::RowVectorXd expected = Eigen::RowVectorXd::Zero(mesh.controls);
    expected(mesh.edge(v, 0)) = 1.0 - mesh.t(v);
    expected(mesh.edge(v, 1)) = mesh.t(v);
    EXPECT_EQ(r.W.row(v), expected) << "edge vertex " << v;
  }
  EXPECT_GT(r.report.iterations, 1);
  EXPECT_LE(r.report.primalResidual, LbcOptions{}.tolerance);
  EXPECT_LE(r.report.dualResidual, LbcOptions{}.tolerance);
}

/// On the star meshed at spacing h: the default solve's objective is within 0.1% of a tight solve's,
/// the duality-gap certificate brackets it, and harmonic coordinates cost clearly more.
void expectObjectiveWithinAThousandthOfATightSolve(double h) {
  const CageMesh mesh = starMesh(h);
  const LbcSolver solver(mesh, LbcTau::Square);
  LbcOptions normalOptions;
  normalOptions.certify = true;
  const LbcResult normal = solver.solve(normalOptions);
  LbcOptions tight;
  tight.tolerance = 1e-10;
  tight.maxIterations = 200000;
  tight.penalty = 0.3;  // a larger, balanced μ converges faster to very small residuals
  tight.adaptivePenalty = true;
  tight.certify = true;
  const LbcResult best = solver.solve(tight);
  ASSERT_EQ(best.report.status, SolveStatus::Ok);
  EXPECT_LE(normal.report.objective, best.report.objective * 1.001);
  EXPECT_GE(normal.report.objective, best.report.objective * (1 - 1e-6));  // the tight solve is the lower one
  EXPECT_EQ(solver.objective(best.W), best.report.objective);

  // The duality-gap certificate: a lower bound (below the tight optimum, weak duality) that closes
  // as ADMM converges; at the default tolerance it already certifies the 0.1% goal on this mesh.
  EXPECT_LE(normal.report.lowerBound, best.report.objective);
  EXPECT_LE(best.report.lowerBound, best.report.objective);
  EXPECT_LT(best.report.objective - best.report.lowerBound, 1e-7 * best.report.objective);
  EXPECT_LT(normal.report.objective - normal.report.lowerBound, 1e-3 * normal.report.lowerBound);

  // The optimization does something: harmonic coordinates (no iteration) cost clearly more.
  LbcOptions none;
  none.maxIterations = 0;
  const LbcResult harmonic = solver.solve(none);
  EXPECT_EQ(harmonic.report.status, SolveStatus::NotConverged);
  EXPECT_GT(harmonic.report.objective, 1.05 * best.report.objective);
}

TEST(LbcSolver, ObjectiveWithinAThousandthOfATightSolve) { expectObjectiveWithinAThousandthOfATightSolve(26.0); }

TEST(LbcSolverSlow, ObjectiveWithinAThousandthOfATightSolveOnAFinerMesh) {
  expectObjectiveWithinAThousandthOfATightSolve(20.0);
}

TEST(LbcSolver, LocalerThanHarmonicCoordinates) {
  // Mean number of controls above 10⁻³/m per interior vertex (paper §5 threshold).
  const CageMesh mesh = starMesh();
  const LbcSolver solver(mesh, LbcTau::Square);
  LbcOptions none;
  none.maxIterations = 0;
  auto influencing = [&](const Weights& W) {
    const double t = 1e-3 / double(mesh.controls);
    double count = 0.0;
    for (Index v = mesh.boundary; v < mesh.size(); ++v) count += double((W.row(v).array() > t).count());
    return count / double(mesh.interior());
  };
  const double lbc = influencing(solver.solve().W), harmonic = influencing(solver.solve(none).W);
  EXPECT_LT(lbc, 0.6 * harmonic) << "LBC " << lbc << " harmonic " << harmonic;
}

TEST(LbcSolver, BitIdenticalOnOneAndTwoThreads) {
  // Large enough that every parallel loop (grains of 64 vertices and 256 triangles) splits in two.
  const CageMesh mesh = starMesh(16.0);
  ASSERT_GT(mesh.interior(), 64);
  ASSERT_GT(std::ssize(mesh.T), 256);
  // 120 iterations cover the first two thread-choice probes (iterations 1-6 and 101-106), which run
  // the loops on both threads whatever the timing picks between them.
  LbcOptions options;
  options.maxIterations = 120;
  LbcResult one, two;
  {
    ScopedThreadCount threads(1);
    one = solveLbc(mesh, options);
  }
  {
    ScopedThreadCount threads(2);
    two = solveLbc(mesh, options);
  }
  ASSERT_EQ(one.report.iterations, 120);
  ASSERT_EQ(one.report.iterations, two.report.iterations);
  ASSERT_EQ(one.W.size(), two.W.size());
  EXPECT_EQ(0, std::memcmp(one.W.data(), two.W.data(), sizeof(double) * std::size_t(one.W.size())));
  EXPECT_EQ(one.report.objective, two.report.objective);
}

TEST(LbcSolver, EveryTauGivesBarycentricWeights) {
  const CageMesh mesh = meshCageInterior(test::lCage(), {.spacing = 20.0, .sizing = nullptr});
  ASSERT_GT(mesh.interior(), 50);
  for (LbcTau tau : {LbcTau::Square, LbcTau::Constant, LbcTau::Linear, LbcTau::Sqrt}) {
    LbcOptions options;
    options.tau = tau;
    const LbcResult r = solveLbc(mesh, options);
    EXPECT_EQ(r.report.status, SolveStatus::Ok) << int(tau);
    const auto [pu, rep] = affineErrors(mesh, r.W);
    EXPECT_LE(pu, 1e-9) << int(tau);
    EXPECT_LE(rep, 1e-9) << int(tau);
    EXPECT_GE(r.W.minCoeff(), 0.0) << int(tau);
  }
  const LbcSolver linear(mesh, LbcTau::Linear);
  EXPECT_THROW(linear.solve(LbcOptions{}), std::invalid_argument) << "φ was built for another τ";
  LbcOptions same;
  same.tau = LbcTau::Linear;
  EXPECT_EQ(linear.solve(same).report.status, SolveStatus::Ok);
  EXPECT_EQ(lbcTau(LbcTau::Square, 0.5), 0.25);
  EXPECT_EQ(lbcTau(LbcTau::Constant, 0.5), 1.0);
  EXPECT_EQ(lbcTau(LbcTau::Linear, 0.5), 0.5);
  EXPECT_EQ(lbcTau(LbcTau::Sqrt, 0.25), 0.5);
}

TEST(LbcSolver, IterationCapIsReportedAndProgressCancels) {
  const CageMesh mesh = starMesh();
  LbcOptions capped;
  capped.maxIterations = 3;
  const LbcResult r = solveLbc(mesh, capped);
  EXPECT_EQ(r.report.status, SolveStatus::NotConverged);
  EXPECT_EQ(r.report.iterations, 3);
  const auto [pu, rep] = affineErrors(mesh, r.W);  // still exact barycentric weights
  EXPECT_LE(pu, 1e-9);
  EXPECT_LE(rep, 1e-9);

  // Progress every 10 iterations, in [0, 1] and never decreasing; false at the second call stops
  // the iteration there with kc::Cancelled.
  LbcOptions cancelled;
  std::vector<double> fractions;
  cancelled.progress = [&](double f) {
    fractions.push_back(f);
    return fractions.size() < 2;
  };
  EXPECT_THROW(solveLbc(mesh, cancelled), Cancelled);
  ASSERT_EQ(fractions.size(), 2u);
  EXPECT_GT(fractions[0], 0.0);
  EXPECT_LE(fractions[0], fractions[1]);
  EXPECT_LE(fractions[1], 1.0);
}

TEST(LbcSolver, RejectsAnUnfinishedMesh) {
  CageMesh empty;
  empty.controls = 10;
  EXPECT_THROW(LbcSolver(empty, LbcTau::Square), std::invalid_argument);
}

}  // namespace
}  // namespace kc
