#include "kc/core/structure/rigidity_qp.h"

#include <Eigen/Dense>
#include <chrono>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>
#include <stdexcept>

#include "../sparse_cholesky.h"

namespace kc {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Solves M̂ Y = rhs subject to A Y = 0 through the factorization of M̂ and the pseudo-inverse of
/// the a×a Schur complement A M̂⁻¹ Aᵀ: Y = Y0 − F (S⁺ A Y0), Y0 = M̂⁻¹ rhs, F = M̂⁻¹ Aᵀ.
class ConstrainedSolve {
 public:
  bool compute(const SparseMatrix& M, const RowMatrix& A, double rankTolerance) {
    m_llt.compute(M);
    if (m_llt.info() != Eigen::Success) return false;
    if (A.rows() == 0) return true;
    m_F = m_llt.solve(Eigen::MatrixXd(A.transpose()));
    const Eigen::MatrixXd S = A * m_F;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (S + S.transpose()));
    const Eigen::VectorXd& d = eig.eigenvalues();
    const double cut = rankTolerance * std::max(d.cwiseAbs().maxCoeff(), 1e-300);
    Eigen::VectorXd inv(d.size());
    for (Index k = 0; k < d.size(); ++k) inv(k) = d(k) > cut ? 1.0 / d(k) : 0.0;
    m_Splus = eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
    m_A = A;
    return true;
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const {
    Eigen::MatrixXd Y = m_llt.solve(rhs);
    if (m_A.rows() > 0) Y -= m_F * (m_Splus * (m_A * Y));
    return Y;
  }

 private:
  detail::SupernodalCholesky m_llt;
  Eigen::MatrixXd m_F, m_Splus;
  RowMatrix m_A;
};

}  // namespace

double rigidityObjective(const RigidityQp& qp, const RowMatrix& dU) {
  return (dU.transpose() * (qp.H * dU)).trace() + 2.0 * dU.cwiseProduct(qp.G).sum();
}

namespace {

/// ADMM (the splitting above) from S = Λ = 0.
RowMatrix solveAdmm(const RigidityQp& qp, const RigidityQpOptions& options, RigidityQpReport& rep,
                    std::chrono::steady_clock::time_point t0) {
  const Index n = qp.H.rows(), m = qp.G.cols(), c = qp.Kc.rows();
  RowMatrix dU = RowMatrix::Zero(n, m);
  const Eigen::MatrixXd GZ = qp.G * qp.Z;  // n×r
  const SparseMatrix H2 = 2.0 * qp.H;
  const double traceH = H2.diagonal().sum();
  SparseMatrix KtK;
  double mu = 0.0;
  if (c > 0) {
    KtK = SparseMatrix(qp.Kc.transpose()) * qp.Kc;
    mu = options.penalty > 0.0 ? options.penalty : traceH / std::max(KtK.diagonal().sum(), 1e-300);
  }
  rep.penalty = mu;
  SparseMatrix M = c > 0 ? SparseMatrix(H2 + mu * KtK) : H2;
  // A tiny diagonal shift keeps the factorization definite where H is only semi-definite.
  SparseMatrix shift(n, n);
  shift.setIdentity();
  M += (1e-13 * std::max(traceH / double(n), 1e-300)) * shift;
  M.makeCompressed();
  const auto tf = std::chrono::steady_clock::now();
  ConstrainedSolve solver;
  if (!solver.compute(M, qp.A, options.rankTolerance)) {
    rep.factorFailed = true;
    rep.seconds = secondsSince(t0);
    return dU;
  }
  rep.factorSeconds = secondsSince(tf);

  Eigen::MatrixXd Y;
  if (c == 0) {  // no inequalities: one equality-constrained solve
    Y = solver.solve(-2.0 * GZ);
    dU = Y * qp.Z.transpose();
    rep.converged = true;
    rep.objective = rigidityObjective(qp, dU);
    rep.seconds = secondsSince(t0);
    return dU;
  }

  const SparseMatrix KcT = qp.Kc.transpose();
  const double alpha = options.relaxation;
  const double dualScale = std::max(2.0 * GZ.cwiseAbs().maxCoeff(), 1e-300);
  RowMatrix S = RowMatrix::Zero(c, m), Lambda = RowMatrix::Zero(c, m), KY(c, m), V(c, m), Snew(c, m);
  for (int it = 1; it <= options.maxIterations; ++it) {
    const Eigen::MatrixXd rhs = -2.0 * GZ + mu * (KcT * ((S - Lambda) * qp.Z));
    Y = solver.solve(rhs);
    KY = (qp.Kc * Y) * qp.Z.transpose();
    V = alpha * KY + (1.0 - alpha) * S;
    Snew = (V + Lambda).cwiseMax(qp.L);
    if (qp.Up.size() > 0) Snew = Snew.cwiseMin(qp.Up);
    Lambda += V - Snew;
    rep.primalResidual = (KY - Snew).cwiseAbs().maxCoeff();
    rep.dualResidual = mu * (KcT * ((Snew - S) * qp.Z)).cwiseAbs().maxCoeff();
    S.swap(Snew);
    rep.iterations = it;
    if (rep.primalResidual <= options.tolerance && rep.dualResidual <= options.dualTolerance * dualScale) {
      rep.converged = true;
      break;
    }
  }
  dU = Y * qp.Z.transpose();
  const RowMatrix KdU = qp.Kc * dU;
  rep.violation = std::max(0.0, (qp.L - KdU).maxCoeff());
  if (qp.Up.size() > 0) rep.violation = std::max(rep.violation, (KdU - qp.Up).maxCoeff());
  rep.objective = rigidityObjective(qp, dU);
  rep.seconds = secondsSince(t0);
  return dU;
}

/// Primal-dual active set (Hintermüller, Ito & Kunisch 2002) on the lower bounds Kc ΔU ≥ L: one
/// factorization of 2H (with A through the Schur complement); the equality-constrained optimum Y0;
/// then rounds of: the active pairs (sample i, control col) are held at their bounds by the
/// multipliers λ of the dense system Σ_b (k_iᵀ F_j)(z_col·z_d) λ_b = L_a − (Kc Y0 Zᵀ)_a with
/// F_j = (2H)⁻¹_A k_j (the constrained solve of row j of Kc); Y = Y0 + Σ_b λ_b F_j z_dᵀ; the next
/// active set keeps the pairs with λ > 0 and adds the violated ones. It stops when the set repeats:
/// then λ ≥ 0 on it and Kc ΔU ≥ L − tolerance off it (the KKT conditions). Returns false (and
/// leaves dU alone) when it does not settle within maxActiveSetRounds or the set grows past
/// maxActivePairs: the caller falls back to ADMM.
bool solveActiveSet(const RigidityQp& qp, const RigidityQpOptions& options, RigidityQpReport& rep, RowMatrix& dU) {
  const Index n = qp.H.rows(), m = qp.G.cols(), c = qp.Kc.rows();
  const SparseMatrix H2 = 2.0 * qp.H;
  SparseMatrix M = H2;
  SparseMatrix shift(n, n);
  shift.setIdentity();
  M += (1e-13 * std::max(H2.diagonal().sum() / double(n), 1e-300)) * shift;
  M.makeCompressed();
  const auto tf = std::chrono::steady_clock::now();
  ConstrainedSolve solver;
  if (!solver.compute(M, qp.A, options.rankTolerance)) return false;
  rep.factorSeconds = secondsSince(tf);
  const Eigen::MatrixXd Y0 = solver.solve(-2.0 * (qp.G * qp.Z));
  const SparseRowMatrix Kr = qp.Kc;
  const RowMatrix S0 = (qp.Kc * Y0) * qp.Z.transpose();
  const Eigen::MatrixXd ZZ = qp.Z * qp.Z.transpose();  // m×m
  const double tol = options.tolerance;

  std::vector<Index> column(static_cast<std::size_t>(c), -1);  // sample row → column of F (computed on demand)
  Eigen::MatrixXd F(n, 0);
  // The columns F_i of the rows in `pairs` not computed yet, in one multi-right-hand-side solve.
  auto addColumns = [&](const std::vector<std::pair<Index, Index>>& pairs) {
    std::vector<Index> fresh;
    for (const auto& [i, col] : pairs)
      if (column[std::size_t(i)] < 0) column[std::size_t(i)] = F.cols() + Index(fresh.size()), fresh.push_back(i);
    if (fresh.empty()) return;
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, Index(fresh.size()));
    for (std::size_t f = 0; f < fresh.size(); ++f)
      for (SparseRowMatrix::InnerIterator it(Kr, fresh[f]); it; ++it) k(it.col(), Index(f)) = it.value();
    const Eigen::MatrixXd solved = solver.solve(k);
    Eigen::MatrixXd grown(n, F.cols() + solved.cols());
    grown << F, solved;
    F.swap(grown);
  };
  std::vector<std::pair<Index, Index>> active;  // (sample row, control)
  for (Index i = 0; i < c; ++i)
    for (Index col = 0; col < m; ++col)
      if (S0(i, col) < qp.L(i, col) - tol) active.emplace_back(i, col);
  Eigen::MatrixXd Y = Y0;
  Eigen::VectorXd lambda;
  for (int round = 1; round <= options.maxActiveSetRounds; ++round) {
    rep.iterations = round;
    const Index a = Index(active.size());
    if (a > options.maxActivePairs) return false;
    if (a == 0) {
      Y = Y0;
    } else {
      addColumns(active);
      Eigen::MatrixXd KiF(a, F.cols());  // k_iᵀ F_j for the active rows
      for (Index p = 0; p < a; ++p) {
        KiF.row(p).setZero();
        for (SparseRowMatrix::InnerIterator it(Kr, active[std::size_t(p)].first); it; ++it) KiF.row(p) += it.value() * F.row(it.col());
      }
      Eigen::MatrixXd Q(a, a);
      Eigen::VectorXd rhs(a);
      for (Index p = 0; p < a; ++p) {
        const auto [i, ci] = active[std::size_t(p)];
        rhs(p) = qp.L(i, ci) - S0(i, ci);
        for (Index q = 0; q < a; ++q) {
          const auto [j, cj] = active[std::size_t(q)];
          Q(p, q) = KiF(p, column[std::size_t(j)]) * ZZ(ci, cj);
        }
      }
      Q.diagonal().array() += 1e-12 * std::max(Q.diagonal().maxCoeff(), 1e-300);
      lambda = Q.ldlt().solve(rhs);
      Eigen::MatrixXd Lz = Eigen::MatrixXd::Zero(F.cols(), qp.Z.cols());  // Y = Y0 + Σ_p λ_p F_{i_p} z_{c_p}ᵀ
      for (Index p = 0; p < a; ++p) Lz.row(column[std::size_t(active[std::size_t(p)].first)]) += lambda(p) * qp.Z.row(active[std::size_t(p)].second);
      Y = Y0 + F * Lz;
    }
    const RowMatrix S = (qp.Kc * Y) * qp.Z.transpose();
    std::vector<std::pair<Index, Index>> next;
    std::vector<char> in(static_cast<std::size_t>(c * m), 0);
    for (Index p = 0; p < a; ++p)
      if (lambda(p) > 0.0) {
        next.push_back(active[std::size_t(p)]);
        in[std::size_t(active[std::size_t(p)].first * m + active[std::size_t(p)].second)] = 1;
      }
    for (Index i = 0; i < c; ++i)
      for (Index col = 0; col < m; ++col)
        if (!in[std::size_t(i * m + col)] && S(i, col) < qp.L(i, col) - tol) next.emplace_back(i, col);
    std::sort(next.begin(), next.end());
    if (next == active) {
      dU = Y * qp.Z.transpose();
      rep.converged = true;
      return true;
    }
    active.swap(next);
  }
  return false;
}

}  // namespace

RowMatrix solveRigidityQp(const RigidityQp& qp, const RigidityQpOptions& options, RigidityQpReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  RigidityQpReport local;
  RigidityQpReport& rep = report ? *report : local;
  rep = {};
  const Index n = qp.H.rows(), m = qp.G.cols(), r = qp.Z.cols(), c = qp.Kc.rows();
  if (qp.H.cols() != n || qp.G.rows() != n || qp.Z.rows() != m || (qp.A.rows() > 0 && qp.A.cols() != n) ||
      (c > 0 && (qp.Kc.cols() != n || qp.L.rows() != c || qp.L.cols() != m)) ||
      (qp.Up.size() > 0 && (qp.Up.rows() != c || qp.Up.cols() != m)))
    throw std::invalid_argument("solveRigidityQp: inconsistent shapes");
  if (n == 0 || r == 0) {
    rep.converged = true;
    return RowMatrix::Zero(n, m);
  }
  const bool upper = qp.Up.size() > 0 && qp.Up.array().isFinite().any();
  if (options.method == RigidityQpMethod::ActiveSet && !upper) {
    RowMatrix dU;
    if (solveActiveSet(qp, options, rep, dU)) {
      rep.method = RigidityQpMethod::ActiveSet;
      const RowMatrix KdU = qp.Kc * dU;
      rep.violation = c > 0 ? std::max(0.0, (qp.L - KdU).maxCoeff()) : 0.0;
      rep.objective = rigidityObjective(qp, dU);
      rep.seconds = secondsSince(t0);
      return dU;
    }
    rep = {};
  }
  rep.method = RigidityQpMethod::Admm;
  return solveAdmm(qp, options, rep, t0);
}

}  // namespace kc
