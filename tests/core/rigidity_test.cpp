#include "kc/core/structure/rigidity.h"

#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "kc/core/weights/optimizer.h"
#include "point_problems.h"

namespace kc {
namespace {

/// A small random rigidity QP: n nodes, m controls, H sparse positive definite, bounds that bind.
struct RandomQp {
  RigidityQp qp;
  Eigen::MatrixXd Q3;  // m×3: rows of ΔU orthogonal to these (Z spans their complement)
};

RandomQp randomQp(int n, int m, int a, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), p(0.0, 1.0);
  RandomQp r;
  RigidityQp& q = r.qp;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(2 * n, n);
  for (Index i = 0; i < B.size(); ++i)
    if (p(rng) < 0.3) B.data()[i] = u(rng);
  const Eigen::MatrixXd Hd = B.transpose() * B + 0.05 * Eigen::MatrixXd::Identity(n, n);
  q.H = Hd.sparseView();
  q.G = RowMatrix::NullaryExpr(n, m, [&] { return 2.0 * u(rng); });
  r.Q3.resize(m, 3);
  for (int i = 0; i < m; ++i) r.Q3.row(i) << 1.0, u(rng), u(rng);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(r.Q3, Eigen::ComputeFullU);
  q.Z = svd.matrixU().rightCols(m - 3);
  q.A = RowMatrix::NullaryExpr(a, n, [&] { return u(rng); });
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (Index i = 0; i < K.size(); ++i)
    if (p(rng) < 0.4) K.data()[i] = p(rng);
  q.Kc = K.sparseView();
  q.L = RowMatrix::NullaryExpr(n, m, [&] { return p(rng) < 0.3 ? 0.0 : -0.3 * p(rng); });
  return r;
}

/// CLP's QP on the same problem written in ΔU directly (not through Z): min ½uᵀ(2H⊗I)u + 2gᵀu,
/// ΔU Q3 = 0, A ΔU = 0, Kc ΔU ≥ L; u = vec(ΔU) column by column. Returns false without an optimum.
bool clpReference(const RandomQp& r, RowMatrix& dU) {
  const RigidityQp& q = r.qp;
  const int n = int(q.H.rows()), m = int(q.G.cols()), a = int(q.A.rows()), c = int(q.Kc.rows());
  const int cols = n * m, rows = 3 * n + a * m + c * m;
  auto var = [n](int j, int col) { return j + n * col; };
  std::vector<int> ri, ci;
  std::vector<double> v;
  std::vector<double> rlo, rhi;
  auto add = [&](int row, int col, double val) {
    if (val == 0.0) return;
    ri.push_back(row);
    ci.push_back(col);
    v.push_back(val);
  };
  int row = 0;
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < 3; ++k, ++row) {
      for (int col = 0; col < m; ++col) add(row, var(j, col), r.Q3(col, k));
      rlo.push_back(0.0), rhi.push_back(0.0);
    }
  for (int col = 0; col < m; ++col)
    for (int e = 0; e < a; ++e, ++row) {
      for (int j = 0; j < n; ++j) add(row, var(j, col), q.A(e, j));
      rlo.push_back(0.0), rhi.push_back(0.0);
    }
  const Eigen::MatrixXd Kd(q.Kc);
  for (int col = 0; col < m; ++col)
    for (int i = 0; i < c; ++i, ++row) {
      for (int j = 0; j < n; ++j) add(row, var(j, col), Kd(i, j));
      rlo.push_back(q.L(i, col)), rhi.push_back(COIN_DBL_MAX);
    }
  const CoinPackedMatrix M(true, ri.data(), ci.data(), v.data(), CoinBigIndex(v.size()));
  std::vector<double> lo(cols, -COIN_DBL_MAX), hi(cols, COIN_DBL_MAX), obj(cols);
  for (int col = 0; col < m; ++col)
    for (int j = 0; j < n; ++j) obj[var(j, col)] = 2.0 * q.G(j, col);
  ClpSimplex model;
  model.setLogLevel(0);
  model.loadProblem(M, lo.data(), hi.data(), obj.data(), rlo.data(), rhi.data());
  // Quadratic part ½uᵀQu with Q = 2H on each column block (upper triangle, CLP's half matrix).
  const Eigen::MatrixXd Hd(q.H);
  std::vector<CoinBigIndex> start(cols + 1, 0);
  std::vector<int> qc;
  std::vector<double> qv;
  for (int col = 0; col < m; ++col)
    for (int j = 0; j < n; ++j) {
      start[var(j, col)] = CoinBigIndex(qv.size());
      for (int k = j; k < n; ++k)
        if (Hd(j, k) != 0.0) {
          qc.push_back(var(k, col));
          qv.push_back(2.0 * Hd(j, k));
        }
    }
  start[cols] = CoinBigIndex(qv.size());
  model.loadQuadraticObjective(cols, start.data(), qc.data(), qv.data());
  model.setPrimalTolerance(1e-10);
  model.setDualTolerance(1e-10);
  model.primal();
  if (model.status() != 0) return false;
  dU.resize(n, m);
  for (int col = 0; col < m; ++col)
    for (int j = 0; j < n; ++j) dU(j, col) = model.primalColumnSolution()[var(j, col)];
  (void)rows;
  return true;
}

TEST(RigidityQp, MatchesClpOnRandomProblems) {
  int compared = 0, binding = 0, settled = 0;  // settled: solved by the active set itself (no fallback)
  for (unsigned trial = 0; trial < 12; ++trial) {
    const RandomQp r = randomQp(8 + int(trial % 5), 6 + int(trial % 3), int(trial % 3), 100 + trial);
    RowMatrix ref;
    ASSERT_TRUE(clpReference(r, ref)) << "trial " << trial;
    const double fRef = rigidityObjective(r.qp, ref);
    for (const RigidityQpMethod method : {RigidityQpMethod::ActiveSet, RigidityQpMethod::Splitting}) {
      RigidityQpOptions o;
      o.method = method;
      o.tolerance = 1e-9;
      o.splittingTolerance = 1e-10;  // the splitting path run to the end: an independent second solver
      o.splittingDualTolerance = 1e-10;
      o.splittingIterations = 200000;
      RigidityQpReport rep;
      const RowMatrix dU = solveRigidityQp(r.qp, o, &rep);
      const bool activeSet = method == RigidityQpMethod::ActiveSet;
      ASSERT_TRUE(rep.converged) << "trial " << trial << (activeSet ? " active set" : " ADMM") << ": " << rep.iterations;
      if (activeSet && rep.method == RigidityQpMethod::ActiveSet) ++settled;
      const double f = rigidityObjective(r.qp, dU);
      EXPECT_NEAR(f, fRef, 1e-6 * std::max(1.0, std::abs(fRef))) << "trial " << trial << (activeSet ? " active set" : " ADMM");
      // Feasible: rows in span Z, A ΔU = 0, Kc ΔU ≥ L (up to the tolerance).
      EXPECT_LE((dU * r.Q3).cwiseAbs().maxCoeff(), 1e-10);
      if (r.qp.A.rows() > 0) {
        EXPECT_LE((r.qp.A * dU).cwiseAbs().maxCoeff(), 1e-9);
      }
      EXPECT_GE((r.qp.Kc * dU - r.qp.L).minCoeff(), -1e-8);
    }
    // Without the bounds the optimum is lower: the bounds bind on these problems.
    RigidityQp free = r.qp;
    free.Kc.resize(0, free.H.rows());
    free.L.resize(0, free.G.cols());
    if (rigidityObjective(free, solveRigidityQp(free)) < fRef - 1e-6) ++binding;
    ++compared;
  }
  EXPECT_EQ(compared, 12);
  EXPECT_GE(binding, 9);
  // Every one settles: the primal-dual active set used before cycled on 6 of the 12 (degenerate
  // bounds, singular Q_AA) and went through the ADMM fallback.
  EXPECT_EQ(settled, 12);
}

// The dual is taken over working rows (those the unconstrained optimum violates), and rows that
// the solution of that dual violates join later. Here half of the rows keep the unconstrained
// optimum by a margin of 0.01 only, so binding the other half pushes some of them over: the set
// grows, and the answer is still the optimum. CLP's nonlinear primal stops short of the optimum on
// one of these problems (trial 3: −14.546, or −15.886 when asked to go on, against −16.902047084
// here and −16.902047121 from the ADMM, every constraint held to 1e-9; the ADMM takes 0.7 s on it,
// too long for this suite), so each result must be at least as good as CLP's and equal to it to
// 1e-6 on the others.
TEST(RigidityQp, WorkingRowsGrowAndStillReachTheOptimum) {
  int grown = 0, matchClp = 0;
  for (unsigned trial = 0; trial < 8; ++trial) {
    RandomQp r = randomQp(10 + int(trial % 3), 7, int(trial % 2), 300 + trial);
    RigidityQp free = r.qp;
    free.Kc.resize(0, free.H.rows());
    free.L.resize(0, free.G.cols());
    const RowMatrix slack0 = r.qp.Kc * solveRigidityQp(free);  // Kc ΔU at the unconstrained optimum
    for (Index i = 0; i < r.qp.L.rows(); i += 2) r.qp.L.row(i) = (slack0.row(i).array() - 0.01).min(0.0).matrix();
    RowMatrix ref;
    ASSERT_TRUE(clpReference(r, ref)) << "trial " << trial;
    const double fRef = rigidityObjective(r.qp, ref), tol = 1e-6 * std::max(1.0, std::abs(fRef));
    RigidityQpOptions o;
    o.tolerance = 1e-9;
    RigidityQpReport rep;
    const RowMatrix dU = solveRigidityQp(r.qp, o, &rep);
    ASSERT_TRUE(rep.converged) << "trial " << trial;
    EXPECT_EQ(rep.method, RigidityQpMethod::ActiveSet) << "trial " << trial;
    EXPECT_LE(rep.workingRows, r.qp.Kc.rows());
    if (rep.workingSets > 1) ++grown;
    EXPECT_LE((dU * r.Q3).cwiseAbs().maxCoeff(), 1e-10);
    if (r.qp.A.rows() > 0) {
      EXPECT_LE((r.qp.A * dU).cwiseAbs().maxCoeff(), 1e-9);
    }
    EXPECT_GE((r.qp.Kc * dU - r.qp.L).minCoeff(), -1e-8) << "trial " << trial;
    const double f = rigidityObjective(r.qp, dU);
    EXPECT_LE(f, fRef + tol) << "trial " << trial;
    if (std::abs(f - fRef) <= tol) ++matchClp;
  }
  EXPECT_GE(grown, 6);     // the growing path is exercised (measured: 8 of 8)
  EXPECT_GE(matchClp, 7);  // measured: 7 of 8 (trial 3 above)
}

/// Square cage 0..60 with 8 controls, jittered grid samples, QP weights: a bound kernel field.
struct Square {
  SampleSet S;
  Points C;
  Weights W;
  KernelField field;
};

void bindSquare(Square& s, InterpMode mode) {
  s.C.resize(8, 2);
  s.C << 0, 0, 30, 0, 60, 0, 60, 30, 60, 60, 30, 60, 0, 60, 0, 30;
  const Points G = test::jitteredGrid(21, 3.0, 0.2, 3, Vec2(0.0, 0.0));
  std::vector<Index> keepRows;
  for (Index i = 0; i < G.rows(); ++i)
    if (G(i, 0) > 1.5 && G(i, 0) < 58.5 && G(i, 1) > 1.5 && G(i, 1) < 58.5) keepRows.push_back(i);
  s.S.X.resize(8 + Index(keepRows.size()), 2);
  s.S.X.topRows(8) = s.C;
  for (std::size_t k = 0; k < keepRows.size(); ++k) s.S.X.row(8 + Index(k)) = G.row(keepRows[k]);
  s.S.kind.assign(std::size_t(s.S.X.rows()), SampleKind::Interior);
  for (int i = 0; i < 8; ++i) s.S.kind[std::size_t(i)] = SampleKind::Control;
  s.S.edge = decltype(s.S.edge)::Constant(s.S.X.rows(), 2, -1);
  // Targets: normalized inverse squared distances; the per-sample QP makes them reproduce.
  Weights W0(s.S.X.rows(), 8);
  for (Index i = 0; i < W0.rows(); ++i) {
    for (Index c = 0; c < 8; ++c) W0(i, c) = 1.0 / (1e-6 + (s.S.X.row(i) - s.C.row(c)).squaredNorm());
    W0.row(i) /= W0.row(i).sum();
  }
  const WeightOptimizer opt(s.C);
  opt.optimize(s.S, W0, s.W, {});
  ASSERT_EQ(s.field.compute(s.S.X, test::kernelFor(3.0), mode).status, SolveStatus::Ok);
  s.field.update(s.W);
}

TEST(Rigidity, FlattensTheRegionKeepsPropertiesAndLeavesFarWeights) {
  Square s;
  bindSquare(s, InterpMode::Exact);
  RigidRegion region;
  region.polygon.resize(3, 2);
  region.polygon << 20, 22, 42, 24, 30, 42;
  const std::vector<double> rho = rigidityOfRegions(s.S.X, std::span(&region, 1));
  std::vector<char> keep(rho.size(), 0);
  for (int i = 0; i < 8; ++i) keep[std::size_t(i)] = 1;
  const Points P = test::randomPointsIn(2000, 6.0, 54.0, 9);
  const Weights before = s.field.weightsAt(P);
  Weights W = s.W;
  const RigidityReport rep = makeRigid(s.field, s.C, rho, keep, W);
  ASSERT_GT(rep.region, 10);
  EXPECT_TRUE(rep.solver.converged);
  // The floor is the least-norm gradient that reproduction allows (Σ_c c_c ∇w_cᵀ = I): about
  // 0.076 here; the region keeps a band of fidelity around it, so the energy drops ~30%.
  EXPECT_LT(rep.energyAfter, 0.75 * rep.energyBefore);
  EXPECT_GE(rep.minWeight, -1e-7);
  const Weights after = s.field.weightsAt(P);
  EXPECT_LE((after.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-9);
  EXPECT_LE((after * s.C - P).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT((after - before).cwiseAbs().maxCoeff(), 1e-3);  // something changed
  const double sigma = s.field.interpolator().kernel().sigma;
  auto changeBeyond = [&](double far, int& points) {
    double change = 0.0;
    for (Index p = 0; p < P.rows(); ++p) {
      bool isFar = true;
      for (Index i = 0; i < s.S.X.rows() && isFar; ++i) isFar = rho[std::size_t(i)] == 0.0 || (P.row(p) - s.S.X.row(i)).norm() > far;
      if (!isFar) continue;
      ++points;
      change = std::max(change, (after.row(p) - before.row(p)).cwiseAbs().maxCoeff());
    }
    return change;
  };
  // Farther than 6σ from every region sample only the re-interpolation's global term is left
  // (docs/rigidity.md). It grows toward the edge of the samples, which here is the cage (2.7e-3
  // there); P keeps 2σ inside it (measured 2.0e-4). Sessions sample the whole picture: the bound
  // ≤ 1e-4 beyond 6σ is checked on the star in tests/app/rigidity_test.cpp.
  int farPoints = 0;
  EXPECT_LE(changeBeyond(6.0 * sigma, farPoints), 1e-3);
  EXPECT_GT(farPoints, 50);
  // Controls (held) keep Lagrange.
  EXPECT_LE((s.field.weightsAt(s.C) - Weights::Identity(8, 8)).cwiseAbs().maxCoeff(), 1e-9);
  // Reloading from W gives the same field (the field is the interpolant of the stored W).
  KernelField reloaded;
  ASSERT_EQ(reloaded.compute(s.S.X, test::kernelFor(3.0)).status, SolveStatus::Ok);
  reloaded.update(W);
  EXPECT_LE((reloaded.weightsAt(P) - after).cwiseAbs().maxCoeff(), 1e-10);
}

// The large-region path (RigidityQpMethod::Splitting, to a moderate tolerance) on the same region:
// after the row projection every painted sample keeps its bound exactly, partition of unity and
// reproduction stay exact, and the energy is the active set's to 1%.
TEST(Rigidity, SplittingPathKeepsBoundsAndPropertiesExactly) {
  RigidRegion region;
  region.polygon.resize(3, 2);
  region.polygon << 20, 22, 42, 24, 30, 42;
  double energy[2] = {0.0, 0.0};
  for (const RigidityQpMethod method : {RigidityQpMethod::ActiveSet, RigidityQpMethod::Splitting}) {
    Square s;
    bindSquare(s, InterpMode::Exact);
    const std::vector<double> rho = rigidityOfRegions(s.S.X, std::span(&region, 1));
    std::vector<char> keep(rho.size(), 0);
    for (int i = 0; i < 8; ++i) keep[std::size_t(i)] = 1;
    Weights W = s.W;
    RigidityOptions o;
    o.solver.method = method;
    const RigidityReport rep = makeRigid(s.field, s.C, rho, keep, W, o);
    ASSERT_EQ(rep.solver.method, method);
    energy[method == RigidityQpMethod::Splitting] = rep.energyAfter;
    for (Index i = 0; i < W.rows(); ++i)
      if (rho[std::size_t(i)] > 0.0 && !keep[std::size_t(i)]) {
        EXPECT_GE((W.row(i) - s.W.row(i).cwiseMin(0.0)).minCoeff(), 0.0) << "sample " << i;
      }
    EXPECT_LE((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
    EXPECT_LE((W * s.C - s.S.X).cwiseAbs().maxCoeff(), 1e-10);
    const Points P = test::randomPointsIn(500, 6.0, 54.0, 9);
    const Weights after = s.field.weightsAt(P);
    EXPECT_LE((after.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-9);
    EXPECT_LE((after * s.C - P).cwiseAbs().maxCoeff(), 1e-9);
  }
  EXPECT_NEAR(energy[1], energy[0], 0.01 * energy[0]);
}

TEST(Rigidity, StrengthBlendsFromUnconstrainedToRigid) {
  double last = 0.0;
  for (double strength : {0.0, 0.25, 0.5, 1.0}) {
    Square s;
    bindSquare(s, InterpMode::Exact);
    RigidRegion region{Points(3, 2), strength};
    region.polygon << 20, 22, 42, 24, 30, 42;
    const std::vector<double> rho = rigidityOfRegions(s.S.X, std::span(&region, 1));
    std::vector<char> keep(rho.size(), 0);
    Weights W = s.W;
    const RigidityReport rep = makeRigid(s.field, s.C, rho, keep, W);
    if (strength == 0.0) {
      EXPECT_EQ(rep.region, 0);
      EXPECT_TRUE(W == s.W);
      Weights dx, dy;
      Points XI(0, 2);
      for (Index i = 0; i < s.S.X.rows(); ++i)
        if (insidePolygon(region.polygon, s.S.X.row(i).transpose())) {
          XI.conservativeResize(XI.rows() + 1, 2);
          XI.row(XI.rows() - 1) = s.S.X.row(i);
        }
      s.field.gradientsAt(XI, dx, dy);
      const double sigma = s.field.interpolator().kernel().sigma;
      last = sigma * sigma * (dx.squaredNorm() + dy.squaredNorm());
      continue;
    }
    const double e = rep.energyAfter / strength;  // Σ σ²‖∇w‖² over the region (ρ = strength there)
    EXPECT_LT(e, last) << "strength " << strength;
    last = e;
  }
}

TEST(RigidRegions, RefusesBadPolygons) {
  const Cage cage = Cage::polygon((Points(4, 2) << 0, 0, 100, 0, 100, 100, 0, 100).finished());
  auto check = [&](const Points& P, double s, const char* what) {
    const RigidRegion r{P, s};
    try {
      validateRigidRegions(cage, std::span(&r, 1));
      ADD_FAILURE() << "accepted: " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("rigid[0]"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  check((Points(2, 2) << 10, 10, 20, 20).finished(), 1.0, "at least 3 points");
  check((Points(3, 2) << 10, 10, 20, 10, 15, 20).finished(), 1.5, "strength");
  check((Points(3, 2) << 10, 10, 20, 10, 15, 20).finished(), std::nan(""), "strength");
  check((Points(3, 2) << 10, 10, 120, 10, 15, 20).finished(), 1.0, "outside the cage");
  check((Points(4, 2) << 10, 10, 40, 40, 40, 10, 10, 20).finished(), 1.0, "intersects itself");
  check((Points(3, 2) << 10, 10, std::nan(""), 10, 15, 20).finished(), 1.0, "finite");
  const Cage notch = Cage::polygon((Points(5, 2) << 0, 0, 100, 0, 100, 100, 50, 20, 0, 100).finished());
  const RigidRegion across{(Points(3, 2) << 30, 50, 70, 50, 50, 10).finished(), 1.0};
  EXPECT_THROW(validateRigidRegions(notch, std::span(&across, 1)), std::invalid_argument);
  const RigidRegion fine{(Points(3, 2) << 10, 10, 20, 10, 15, 20).finished(), 0.5};
  EXPECT_NO_THROW(validateRigidRegions(cage, std::span(&fine, 1)));
}

}  // namespace
}  // namespace kc
