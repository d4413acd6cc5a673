// The rigidity QP's path for large regions (core/src/structure/rigidity_admm.h): the row
// projection that makes the stored weights exact, and the splitting solver against the active set.

#include <gtest/gtest.h>

#include <cstdio>

#include <Eigen/Dense>
#include <random>

#include "../../core/src/structure/rigidity_admm.h"
#include "kc/core/structure/rigidity_qp.h"

namespace kc {
namespace {

/// An orthonormal basis Z (m×(m−3)) of {v : 1ᵀv = 0, Cᵀv = 0} for random controls C, and Q3 = [1 C].
void randomMoments(int m, std::mt19937& rng, RowMatrix& Z, Eigen::MatrixXd& Q3) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Q3.resize(m, 3);
  for (int i = 0; i < m; ++i) Q3.row(i) << 1.0, u(rng), u(rng);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Q3, Eigen::ComputeFullU);
  Z = svd.matrixU().rightCols(m - 3);
}

/// The Euclidean projection of v onto {s ≥ l, Q3ᵀs = 0} by enumeration: the optimum lies in the
/// relative interior of a face {s_A = l_A}, where it is the least-squares point of that face's affine
/// hull; among all feasible such points the nearest is the projection.
double bruteForceDistance(const Eigen::VectorXd& v, const Eigen::VectorXd& l, const Eigen::MatrixXd& Q3) {
  const int m = int(v.size());
  double best = std::numeric_limits<double>::infinity();
  for (unsigned mask = 0; mask < (1u << m); ++mask) {
    std::vector<int> fixed, free;
    for (int j = 0; j < m; ++j) ((mask >> j) & 1u ? fixed : free).push_back(j);
    // min ‖s_F − v_F‖² s.t. Q3_Fᵀ s_F = −Q3_Aᵀ l_A: s_F = v_F − Q3_F μ with (Q3_FᵀQ3_F) μ = Q3_Fᵀ v_F + Q3_Aᵀ l_A.
    Eigen::MatrixXd QF(free.size(), 3);
    Eigen::VectorXd vF(free.size());
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (std::size_t a = 0; a < free.size(); ++a) QF.row(Index(a)) = Q3.row(free[a]), vF(Index(a)) = v(free[a]);
    for (int j : fixed) rhs += Q3.row(j).transpose() * l(j);
    rhs += QF.transpose() * vF;
    const Eigen::Matrix3d N = QF.transpose() * QF;
    Eigen::VectorXd s(m);
    for (int j : fixed) s(j) = l(j);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(N);
    const Eigen::VectorXd sF = vF - QF * cod.solve(rhs);
    for (std::size_t a = 0; a < free.size(); ++a) s(free[a]) = sF(Index(a));
    if ((Q3.transpose() * s).cwiseAbs().maxCoeff() > 1e-9 || (s - l).minCoeff() < -1e-12) continue;  // infeasible face
    best = std::min(best, (s - v).norm());
  }
  return best;
}

TEST(RigidityRows, ProjectionIsTheEuclideanOneAndExact) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), p(0.0, 1.0);
  int projected = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int m = 5 + trial % 5;
    RowMatrix Z;
    Eigen::MatrixXd Q3;
    randomMoments(m, rng, Z, Q3);
    const detail::RowPolytope poly(Z);
    ASSERT_EQ(poly.size(), m);
    // l ≤ 0 (0 is feasible); v in span Z (the solver's rows) or not (any point).
    Eigen::VectorXd l(m), v(m), s(m);
    for (int j = 0; j < m; ++j) l(j) = p(rng) < 0.4 ? 0.0 : -0.3 * p(rng);
    v = Z * Eigen::VectorXd::NullaryExpr(m - 3, [&] { return u(rng); });
    if (trial % 3 == 0) v += 0.2 * Eigen::VectorXd::NullaryExpr(m, [&] { return u(rng); });
    Eigen::Vector3d nu = Eigen::Vector3d::Zero();
    EXPECT_TRUE(poly.project(v.data(), l.data(), s.data(), nu)) << "trial " << trial;
    // The moments to round-off: the Newton point is kept at 1e-11 when a degenerate bound (an entry
    // at its bound with a zero multiplier) leaves the exact solve on the free entries unverified.
    EXPECT_LE((Q3.transpose() * s).cwiseAbs().maxCoeff(), 1e-11) << "trial " << trial;
    EXPECT_GE((s - l).minCoeff(), 0.0) << "trial " << trial;
    EXPECT_NEAR((s - v).norm(), bruteForceDistance(v, l, Q3), 1e-10) << "trial " << trial;
    if ((v - l).minCoeff() < 0.0) ++projected;
  }
  EXPECT_GT(projected, 30);  // most rows violate a bound (the projection is exercised)
}

TEST(RigidityRows, ProjectRowsChangesOnlyViolatedRowsInTheActiveControls) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int mActive = 7, m = 9;  // controls 2 and 6 inactive (zero rows of Z)
  RowMatrix Zs;
  Eigen::MatrixXd Q3;
  randomMoments(mActive, rng, Zs, Q3);
  const std::vector<Index> ctl = {0, 1, 3, 4, 5, 7, 8};
  RowMatrix Z = RowMatrix::Zero(m, mActive - 3);
  for (int k = 0; k < mActive; ++k) Z.row(ctl[std::size_t(k)]) = Zs.row(k);
  RowMatrix dW = RowMatrix::Zero(12, m), L = RowMatrix::Constant(6, m, -0.05);
  for (Index i = 0; i < 12; ++i) dW.row(i) = Z * Eigen::VectorXd::NullaryExpr(mActive - 3, [&] { return 0.1 * u(rng); });
  dW.row(0) = 0.01 * dW.row(0);  // keeps its bounds
  const std::vector<Index> rows = {0, 2, 4, 6, 8, 10};
  const RowMatrix before = dW;
  const detail::RowProjection rep = detail::projectRows(Z, L, rows, dW);
  EXPECT_GT(rep.changed, 0);
  EXPECT_EQ(rep.fallbacks, 0);
  EXPECT_TRUE(dW.row(0) == before.row(0));
  for (Index i = 1; i < 12; i += 2) EXPECT_TRUE(dW.row(i) == before.row(i));  // not in the list
  for (std::size_t r = 0; r < rows.size(); ++r) {
    EXPECT_GE((dW.row(rows[r]) - L.row(Index(r))).minCoeff(), 0.0);
    EXPECT_EQ(dW(rows[r], 2), 0.0);
    EXPECT_EQ(dW(rows[r], 6), 0.0);
    Eigen::VectorXd d(mActive);
    for (int k = 0; k < mActive; ++k) d(k) = dW(rows[r], ctl[std::size_t(k)]);
    EXPECT_LE((Q3.transpose() * d).cwiseAbs().maxCoeff(), 1e-13);
  }
}

/// A random rigidity QP of moderate size: n nodes with kernel-like sparse rows (each node couples
/// to its neighbours in a ring), m controls, bounds that bind, a held rows.
RigidityQp randomQp(int n, int m, int a, unsigned seed, Eigen::MatrixXd& Q3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), p(0.0, 1.0);
  RigidityQp q;
  randomMoments(m, rng, q.Z, Q3);
  std::vector<Eigen::Triplet<double>> b, k;
  for (int i = 0; i < 2 * n; ++i)
    for (int d = -4; d <= 4; ++d) b.emplace_back(i, ((i / 2 + d) % n + n) % n, std::exp(-0.2 * d * d) * (1.0 + 0.3 * u(rng)));
  for (int i = 0; i < n; ++i)
    for (int d = -3; d <= 3; ++d) k.emplace_back(i, ((i + d) % n + n) % n, std::exp(-0.3 * d * d));
  SparseMatrix B(2 * n, n), K(n, n);
  B.setFromTriplets(b.begin(), b.end());
  K.setFromTriplets(k.begin(), k.end());
  SparseMatrix I(n, n);
  I.setIdentity();
  q.H = SparseMatrix(B.transpose()) * B + 0.1 * I;
  q.G = RowMatrix::NullaryExpr(n, m, [&] { return 3.0 * u(rng); });
  q.A = RowMatrix::NullaryExpr(a, n, [&] { return u(rng); });
  for (Index e = 0; e < a; ++e) q.A.row(e).normalize();
  q.Kc = K;
  q.L = RowMatrix::NullaryExpr(n, m, [&] { return p(rng) < 0.3 ? 0.0 : -0.2 * p(rng); });
  return q;
}

// The splitting path stops at a violation of 1e-4 and a relative dual residual of 1e-3; its
// objective is then within 1e-3 (relative) of the active set's exact optimum on these problems,
// and the row projection afterwards makes every bound hold exactly while the moments stay.
TEST(RigidityQp, SplittingIsNearTheActiveSetAndItsRowsProjectExactly) {
  int binding = 0;
  for (unsigned trial = 0; trial < 6; ++trial) {
    Eigen::MatrixXd Q3;
    const RigidityQp qp = randomQp(60 + 20 * int(trial % 3), 8 + int(trial % 3), int(trial % 2) * 3, 40 + trial, Q3);
    RigidityQpOptions exact;
    exact.tolerance = 1e-9;
    RigidityQpReport ra, rs;
    const RowMatrix dA = solveRigidityQp(qp, exact, &ra);
    ASSERT_TRUE(ra.converged) << "trial " << trial << " " << int(ra.method) << " " << ra.iterations;
    ASSERT_EQ(ra.method, RigidityQpMethod::ActiveSet);
    RigidityQpOptions split;
    split.method = RigidityQpMethod::Splitting;
    const RowMatrix dS = solveRigidityQp(qp, split, &rs);
    ASSERT_EQ(rs.method, RigidityQpMethod::Splitting);
    EXPECT_TRUE(rs.converged) << "trial " << trial << ": " << rs.iterations << " iterations";
    std::printf("trial %u: splitting %d iterations\n", trial, rs.iterations);
    EXPECT_LE(rs.violation, 1e-4) << "trial " << trial;
    const double fA = rigidityObjective(qp, dA), fS = rigidityObjective(qp, dS);
    EXPECT_NEAR(fS, fA, 1e-3 * std::abs(fA)) << "trial " << trial;
    EXPECT_LE((dS * Q3).cwiseAbs().maxCoeff(), 1e-12);
    if (qp.A.rows() > 0) {
      EXPECT_LE((qp.A * dS).cwiseAbs().maxCoeff(), 1e-9);
    }
    // The stored rows: Kc ΔU projected.
    RowMatrix dW = qp.Kc * dS;
    std::vector<Index> rows(std::size_t(dW.rows()));
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = Index(i);
    const detail::RowProjection pr = detail::projectRows(qp.Z, qp.L, rows, dW);
    EXPECT_EQ(pr.fallbacks, 0);
    EXPECT_LE(pr.largest, 10.0 * std::max(rs.violation, 1e-12)) << "trial " << trial;  // a change of the violation's size
    EXPECT_GE((dW - qp.L).minCoeff(), 0.0) << "trial " << trial;
    EXPECT_LE((dW * Q3).cwiseAbs().maxCoeff(), 1e-12);
    RigidityQp free = qp;
    free.Kc.resize(0, qp.H.rows());
    free.L.resize(0, qp.G.cols());
    if (rigidityObjective(free, solveRigidityQp(free)) < fA - 1e-6 * std::abs(fA)) ++binding;
  }
  EXPECT_GE(binding, 5);  // the bounds bind
}

TEST(RigidityQp, LargeProblemsTakeTheSplittingPath) {
  Eigen::MatrixXd Q3;
  const RigidityQp qp = randomQp(60, 8, 0, 5, Q3);
  RigidityQpOptions o;
  o.largePairs = 60 * 8 - 1;  // 60 rows × 8 active controls: one pair too many for the active set
  RigidityQpReport rep;
  solveRigidityQp(qp, o, &rep);
  EXPECT_EQ(rep.method, RigidityQpMethod::Splitting);
  o.largePairs = 60 * 8;
  solveRigidityQp(qp, o, &rep);
  EXPECT_EQ(rep.method, RigidityQpMethod::ActiveSet);
}

// An active set that does not settle within its rounds falls back to the splitting path (a few
// dozen iterations), and the answer is near the optimum.
TEST(RigidityQp, AnUnsettledActiveSetFallsBackToTheSplittingPath) {
  Eigen::MatrixXd Q3;
  const RigidityQp qp = randomQp(80, 9, 3, 41, Q3);
  RigidityQpReport exact, limited;
  const double fA = rigidityObjective(qp, solveRigidityQp(qp, {}, &exact));
  ASSERT_EQ(exact.method, RigidityQpMethod::ActiveSet);
  ASSERT_GT(exact.iterations, 1) << "the bounds must need more than one round here";
  RigidityQpOptions o;
  o.maxActiveSetRounds = 1;
  const RowMatrix dU = solveRigidityQp(qp, o, &limited);
  EXPECT_EQ(limited.method, RigidityQpMethod::Splitting);
  EXPECT_TRUE(limited.converged) << limited.iterations << " iterations";
  EXPECT_LE(limited.iterations, o.splittingIterations);
  EXPECT_NEAR(rigidityObjective(qp, dU), fA, 1e-3 * std::abs(fA));
  EXPECT_LE((dU * Q3).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RigidityQp, SplittingHearsCancel) {
  Eigen::MatrixXd Q3;
  const RigidityQp qp = randomQp(80, 9, 3, 6, Q3);
  RigidityQpOptions o;
  o.method = RigidityQpMethod::Splitting;
  int calls = 0;
  o.progress = [&](double f) {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
    return ++calls < 3;
  };
  EXPECT_THROW(solveRigidityQp(qp, o), Cancelled);
  EXPECT_EQ(calls, 3);
}

}  // namespace
}  // namespace kc
