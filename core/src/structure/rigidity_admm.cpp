#include "rigidity_admm.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "rigidity_dual.h"
#include "kc/core/timing.h"

namespace kc::detail {
namespace {

/// Anderson acceleration's memory (the splitting's iterations): differences of this many past iterates.
constexpr int kMemory = 5;

double maxAbs(const Eigen::MatrixXd& M) { return M.size() > 0 ? M.cwiseAbs().maxCoeff() : 0.0; }

/// Anderson acceleration (type II; Walker & Ni 2011) of a fixed-point iteration z ← T(z) in R^size:
/// from the last kMemory differences of the residuals f = T(z) − z and of the values g = T(z),
/// the next point g − ΔG γ with γ = argmin ‖f − ΔF γ‖.
class Anderson {
 public:
  explicit Anderson(Index size) : m_dF(size, kMemory), m_dG(size, kMemory) {}

  /// Drops the stored differences (an extrapolated point was rejected). The next ones are stored
  /// from the first column again: next() reads the first m_stored columns.
  void forget() { m_stored = m_next = 0; }
  /// Drops the stored differences and the last residual (the map itself changed).
  void restart() {
    forget();
    m_fPrev.resize(0);
  }
  /// Records the residual f and value g of the last point; returns the next point and sets
  /// `extrapolated` (false: the plain step, z = g).
  Eigen::VectorXd next(const Eigen::VectorXd& f, const Eigen::VectorXd& g, bool& extrapolated) {
    if (m_fPrev.size() == f.size()) {
      m_dF.col(m_next) = f - m_fPrev;
      m_dG.col(m_next) = g - m_gPrev;
      m_next = (m_next + 1) % kMemory;
      m_stored = std::min(m_stored + 1, kMemory);
    }
    m_fPrev = f;
    m_gPrev = g;
    extrapolated = m_stored > 0;
    if (!extrapolated) return g;
    const auto F = m_dF.leftCols(m_stored), G = m_dG.leftCols(m_stored);
    Eigen::MatrixXd normal = F.transpose() * F;
    normal.diagonal().array() += 1e-10 * std::max(normal.diagonal().maxCoeff(), 1e-300);
    const Eigen::VectorXd gamma = normal.ldlt().solve(F.transpose() * f);
    return g - G * gamma;
  }

 private:
  Eigen::MatrixXd m_dF, m_dG;
  Eigen::VectorXd m_fPrev, m_gPrev;
  int m_stored = 0, m_next = 0;
};

}  // namespace

RowPolytope::RowPolytope(const RowMatrix& Z) {
  for (Index k = 0; k < Z.rows(); ++k)
    if (Z.row(k).squaredNorm() > 0.0) m_controls.push_back(k);
  const Index m = size();
  Eigen::MatrixXd Zs(m, Z.cols());
  for (Index k = 0; k < m; ++k) Zs.row(k) = Z.row(m_controls[std::size_t(k)]);
  // The complement of span Z': eigenvectors of I − Z'Z'ᵀ (Z' has orthonormal columns) of eigenvalue 1.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd::Identity(m, m) - Zs * Zs.transpose());
  m_B = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(m, 3);
  Index k = 0;
  for (Index e = m - 1; e >= 0 && k < 3; --e)
    if (eig.eigenvalues()(e) > 0.5) m_B.col(k++) = eig.eigenvectors().col(e);
}

bool RowPolytope::project(const double* v, const double* l, double* s, Eigen::Vector3d& nu) const {
  const Index m = size();
  const Eigen::Map<const Eigen::VectorXd> V(v, m), Lo(l, m);
  Eigen::Map<Eigen::VectorXd> S(s, m);
  const double tol = 1e-14 * (1.0 + V.cwiseAbs().maxCoeff() + Lo.cwiseAbs().maxCoeff());
  // Most rows are inside their polytope already (in the splitting's iterations, V keeps the
  // moments): they are their own projection.
  if ((V.array() >= Lo.array()).all() && (m_B.transpose() * V).cwiseAbs().maxCoeff() <= tol) {
    S = V;
    return true;
  }
  // The dual q(ν) = min_{s ≥ l} ½‖s − v‖² + νᵀBᵀs is concave, with gradient Bᵀs(ν) and
  // generalized Hessian −BᵀDB (D: the entries of v − Bν above their bound).
  auto dual = [&](const Eigen::Vector3d& x, Eigen::VectorXd& sx) {
    sx = (V - m_B * x).cwiseMax(Lo);
    return 0.5 * (sx - V).squaredNorm() + x.dot(m_B.transpose() * sx);
  };
  Eigen::VectorXd trial(m), cur(m);
  double q = dual(nu, cur);
  for (int it = 0; it < 200; ++it) {
    const Eigen::Vector3d g = m_B.transpose() * cur;
    const double gn = g.cwiseAbs().maxCoeff();
    if (gn <= tol) {
      if (!polish(V, Lo, nu, S)) S = cur;  // the moments hold to tol
      return true;
    }
    Eigen::Matrix3d Hk = 1e-12 * Eigen::Matrix3d::Identity();
    for (Index j = 0; j < m; ++j)
      if (V(j) - m_B.row(j).dot(nu) > Lo(j)) Hk.noalias() += m_B.row(j).transpose() * m_B.row(j);
    Eigen::Vector3d d = Hk.ldlt().solve(g);
    double step = 1.0, qn = 0.0;
    for (int h = 0; h < 40; ++h, step *= 0.5) {
      qn = dual(nu + step * d, trial);
      if (qn >= q + 1e-4 * step * g.dot(d)) break;
    }
    if (!(qn > q)) {
      // No Newton ascent: the free set may be the optimum's already (the exact solve checks it);
      // at round-off (q no longer resolves the ascent) the Newton point is kept; else a gradient
      // step (∇q is 1-Lipschitz, B orthonormal: step 1 ascends).
      if (polish(V, Lo, nu, S)) return true;
      if (gn <= 1e3 * tol) {
        S = cur;
        return true;
      }
      d = g;
      step = 1.0;
      qn = dual(nu + d, trial);
      if (!(qn > q)) break;
    }
    nu += step * d;
    q = qn;
    cur.swap(trial);
  }
  // Not converged: the part of v that keeps the moments, scaled toward 0 (feasible: l ≤ 0).
  const Eigen::VectorXd p = V - m_B * (m_B.transpose() * V);
  double t = 1.0;
  for (Index j = 0; j < m; ++j)
    if (p(j) < Lo(j)) t = std::min(t, Lo(j) / p(j));
  S = std::max(t, 0.0) * p;
  return false;
}

bool RowPolytope::polish(const Eigen::Ref<const Eigen::VectorXd>& v, const Eigen::Ref<const Eigen::VectorXd>& l, Eigen::Vector3d& nu,
                         Eigen::Ref<Eigen::VectorXd> s) const {
  // On the free entries F (v − Bν above the bound) the projection is s_F = v_F − B_F ν with
  // Bᵀs = 0, i.e. (B_FᵀB_F) ν = B_Fᵀv_F + B_Aᵀl_A: solved once more, the moments hold to round-off.
  const Index m = size();
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  std::vector<char> isFree(static_cast<std::size_t>(m), 0);
  for (Index j = 0; j < m; ++j) {
    isFree[std::size_t(j)] = v(j) - m_B.row(j).dot(nu) > l(j);
    if (isFree[std::size_t(j)]) {
      N.noalias() += m_B.row(j).transpose() * m_B.row(j);
      rhs += m_B.row(j).transpose() * v(j);
    } else {
      rhs += m_B.row(j).transpose() * l(j);
    }
  }
  const Index k = Index((m_B.colwise().squaredNorm().array() > 0.0).count());  // the moments (columns of B)
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(N.topLeftCorner(k, k));
  Eigen::Vector3d exact = Eigen::Vector3d::Zero();
  exact.head(k) = ldlt.solve(rhs.head(k));
  bool ok = ldlt.info() == Eigen::Success && exact.allFinite();
  // The KKT conditions of the projection: free entries at or above their bound, fixed ones with
  // v − Bν at or below it (a non-negative multiplier), and the moments.
  const double slack = 1e-12 * (1.0 + v.cwiseAbs().maxCoeff() + l.cwiseAbs().maxCoeff());
  Eigen::VectorXd t(m);
  for (Index j = 0; j < m && ok; ++j) {
    const double free = v(j) - m_B.row(j).dot(exact);
    t(j) = isFree[std::size_t(j)] ? free : l(j);
    ok = isFree[std::size_t(j)] ? free >= l(j) - slack : free <= l(j) + slack;
  }
  if (!ok) return false;
  s = t.cwiseMax(l);
  ok = (m_B.transpose() * s).cwiseAbs().maxCoeff() <= slack;
  if (ok) nu = exact;
  return ok;
}

RowProjection projectRows(const RowMatrix& Z, const RowMatrix& L, std::span<const Index> rows, RowMatrix& dW) {
  RowProjection out;
  const RowPolytope poly(Z);
  const std::vector<Index>& ctl = poly.controls();
  const Index m = poly.size();
  Eigen::VectorXd v(m), l(m), s(m);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const Index i = rows[r];
    bool violated = false;
    for (Index k = 0; k < m; ++k) {
      v(k) = dW(i, ctl[std::size_t(k)]);
      l(k) = L(Index(r), ctl[std::size_t(k)]);
      violated = violated || v(k) < l(k);
    }
    if (!violated) continue;
    Eigen::Vector3d nu = Eigen::Vector3d::Zero();
    if (!poly.project(v.data(), l.data(), s.data(), nu)) ++out.fallbacks;
    ++out.changed;
    out.largest = std::max(out.largest, (s - v).cwiseAbs().maxCoeff());
    for (Index k = 0; k < m; ++k) dW(i, ctl[std::size_t(k)]) = s(k);
  }
  return out;
}

RowMatrix solveSplitting(const RigidityQp& qp, const RigidityQpOptions& options, RigidityQpReport& rep) {
  const auto t0 = std::chrono::steady_clock::now();
  rep.method = RigidityQpMethod::Splitting;
  const Index n = qp.H.rows(), c = qp.Kc.rows();
  double stage = 0.0;
  const Tick tick = progressTick(options.progress, stage);
  const RowPolytope poly(qp.Z);
  const std::vector<Index>& ctl = poly.controls();
  const Index m = poly.size();
  Eigen::MatrixXd Zs(m, qp.Z.cols()), Ls(c, m);
  for (Index k = 0; k < m; ++k) Zs.row(k) = qp.Z.row(ctl[std::size_t(k)]), Ls.col(k) = qp.L.col(ctl[std::size_t(k)]);

  tick();  // the set-up before the solver is heard here
  const SparseMatrix H2 = 2.0 * qp.H, KcT = qp.Kc.transpose(), KtK = KcT * qp.Kc;
  stage = 0.01;
  tick();
  const double traceH = H2.diagonal().sum();
  double mu = options.penalty > 0.0 ? options.penalty : traceH / std::max(KtK.diagonal().sum(), 1e-300);
  const double shift = 1e-13 * std::max(traceH / double(n), 1e-300);  // keeps M definite where H is only semi-definite
  DenseConstrainedSolve solver;
  int factorizations = 0;
  auto factorize = [&] {
    const auto tf = std::chrono::steady_clock::now();
    SparseMatrix M = H2 + mu * KtK;
    M.makeCompressed();
    tick();
    const bool ok = solver.compute(M, 1.0, shift, qp.A, options.rankTolerance, tick);
    rep.factorSeconds += secondsSince(tf);
    ++factorizations;
    return ok;
  };
  stage = 0.02;
  if (!factorize()) {
    rep.factorFailed = true;
    rep.seconds = secondsSince(t0);
    return RowMatrix::Zero(n, qp.G.cols());
  }
  const Eigen::MatrixXd GZ2 = -2.0 * (qp.G * qp.Z);  // n×r
  const double gScale = std::max(maxAbs(GZ2), 1e-300);
  const double alpha = options.relaxation;
  // The iteration is a map (S, U) → (S⁺, U⁺) = T(S, U); it is accelerated by Anderson's method
  // with a safeguard: an extrapolated point whose fixed-point residual ‖T(z) − z‖ exceeds the last
  // accepted one is dropped for the plain step, and the memory starts again.
  const Index N = c * m;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(2 * N), g(2 * N), f(2 * N), gAccepted;
  Eigen::MatrixXd X(c, m), V(c, m), Y, dual;
  Eigen::MatrixXd nu = Eigen::MatrixXd::Zero(c, 3);
  Anderson anderson(2 * N);
  bool extrapolated = false;
  double fAccepted = std::numeric_limits<double>::infinity();
  const int maxIt = std::max(options.splittingIterations, 1);
  Eigen::VectorXd v(m), l(m), s(m);
  for (int it = 1; it <= maxIt; ++it) {
    const Eigen::Map<const Eigen::MatrixXd> S(z.data(), c, m), U(z.data() + N, c, m);
    Eigen::Map<Eigen::MatrixXd> Snew(g.data(), c, m), Unew(g.data() + N, c, m);
    Y = solver.solve(GZ2 + mu * (KcT * ((S - U) * Zs)));
    X = (qp.Kc * Y) * Zs.transpose();
    V = alpha * X + (1.0 - alpha) * S;
    Unew = V + U;  // projected below
    for (Index i = 0; i < c; ++i) {
      v = Unew.row(i).transpose();
      l = Ls.row(i).transpose();
      Eigen::Vector3d w = nu.row(i).transpose();
      poly.project(v.data(), l.data(), s.data(), w);
      nu.row(i) = w.transpose();
      Snew.row(i) = s.transpose();
    }
    Unew = U + V - Snew;
    // Residuals (OSQP's): primal max |Kc Y Z'ᵀ − S| in weights; dual 2HY + 2GZ + Kcᵀ(μU)Z' (modulo
    // the equalities), which the Y-step's optimality condition gives as μ Kcᵀ(S − X + V − S⁺) Z'.
    rep.primalResidual = maxAbs(X - Snew);
    dual = mu * (KcT * ((S - X + V - Snew) * Zs));
    rep.dualResidual = maxAbs(dual) / gScale;
    rep.iterations = it;
    f = g - z;
    const double fn = f.norm();
    stage = 0.1 + 0.85 * double(it) / maxIt;
    tick();
    if (rep.primalResidual <= options.splittingTolerance && rep.dualResidual <= options.splittingDualTolerance) {
      rep.converged = true;
      break;
    }
    if (extrapolated && !(fn <= fAccepted)) {  // the safeguard: back to the plain step from the last accepted point
      z = gAccepted;
      anderson.forget();
      extrapolated = false;
      continue;
    }
    // OSQP's adaptive penalty: μ ← μ √(relative primal / relative dual residual), applied (a new
    // factorization) only when it changes by more than 5×.
    if (it % 10 == 0 && factorizations <= options.splittingRefactorizations) {
      const double rp = rep.primalResidual / std::max({maxAbs(X), maxAbs(Snew), 1e-300});
      const double rd = maxAbs(dual) / std::max({gScale, mu * maxAbs(KcT * (Unew * Zs))});
      const double ratio = std::sqrt(rp / std::max(rd, 1e-300));
      if (std::isfinite(ratio) && (ratio > 5.0 || ratio < 0.2)) {
        mu *= ratio;
        g.tail(N) /= ratio;  // the multipliers μU are kept
        if (!factorize()) {
          rep.factorFailed = true;
          break;
        }
        z = g;
        anderson.restart();
        extrapolated = false;
        fAccepted = std::numeric_limits<double>::infinity();
        continue;
      }
    }
    gAccepted = g;
    fAccepted = fn;
    z = anderson.next(f, g, extrapolated);
  }
  rep.penalty = mu;
  const RowMatrix dU = Y * qp.Z.transpose();
  const RowMatrix KdU = qp.Kc * dU;
  rep.violation = c > 0 ? std::max(0.0, (qp.L - KdU).maxCoeff()) : 0.0;
  rep.objective = rigidityObjective(qp, dU);
  rep.seconds = secondsSince(t0);
  return dU;
}

}  // namespace kc::detail
