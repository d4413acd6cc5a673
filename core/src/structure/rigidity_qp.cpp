#include "kc/core/structure/rigidity_qp.h"

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
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
  RowMatrix dU = RowMatrix::Zero(n, m);
  if (n == 0 || r == 0) {
    rep.converged = true;
    return dU;
  }
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

}  // namespace kc
