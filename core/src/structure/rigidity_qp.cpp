#include "kc/core/structure/rigidity_qp.h"

#include <Eigen/Dense>
#include <omp.h>
#include <chrono>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>
#include <stdexcept>

#include "../sparse_cholesky.h"
#include "rigidity_admm.h"
#include "rigidity_dual.h"
#include "kc/core/timing.h"

namespace kc {
namespace {

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
    m_Splus = detail::symmetricPseudoInverse(S, rankTolerance);
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

/// The bounds' dual (docs/rigidity.md, "The QP and its solver"): with F = (2H)⁻¹_A Kcᵀ (n×c),
/// Kq = Kc F (c×c), the active controls' rows Z' of Z (m'×r), P = Z'Z'ᵀ and S0 = Kc Y0 Z'ᵀ, the
/// primal Y(Λ) = Y0 + F Λ Z' for multipliers Λ ≥ 0 (c×m'); its slack S(Λ) − L = Kq Λ P − R with
/// R = L − S0 is the gradient of d(Λ) = ½⟨Λ, Kq Λ P⟩ − ⟨R, Λ⟩, minimized over Λ ≥ 0 (the KKT
/// conditions: Λ ≥ 0, slack ≥ 0, Λ ∘ slack = 0). Q = Kq ⊗ P is never formed: Q Λ = Kq Λ P.
class BoundDual {
 public:
  /// Kq and P are referenced (the working Gram matrix, c×c, is not copied).
  BoundDual(const Eigen::MatrixXd& Kq, const Eigen::MatrixXd& P, Eigen::MatrixXd R) : m_Kq(Kq), m_P(P), m_R(std::move(R)) {}
  Index rows() const { return m_R.rows(); }
  Index cols() const { return m_R.cols(); }
  const Eigen::MatrixXd& R() const { return m_R; }
  /// Q Λ = Kq Λ P (c×m').
  Eigen::MatrixXd apply(const Eigen::MatrixXd& Lambda) const { return m_Kq * (Lambda * m_P); }
  double diagonal(Index i, Index c) const { return m_Kq(i, i) * m_P(c, c); }
  double kq(Index i, Index j) const { return m_Kq(i, j); }
  double p(Index c, Index d) const { return m_P(c, d); }
  const Eigen::MatrixXd& Kq() const { return m_Kq; }
  const Eigen::MatrixXd& P() const { return m_P; }

 private:
  const Eigen::MatrixXd& m_Kq;
  const Eigen::MatrixXd& m_P;
  Eigen::MatrixXd m_R;
};

/// Solves (Q_FF + δI) d = b on the free pairs F by conjugate gradients preconditioned with the
/// per-sample blocks Kq_ii P[F_i, F_i] + δI (Q_FF restricted to one sample's free controls).
/// `free` is c×m' (1 = free); b and the result are c×m' with zeros off F; tick() every 2
/// iterations. Returns the iterations.
int solveFree(const BoundDual& D, const Eigen::Matrix<char, Eigen::Dynamic, Eigen::Dynamic>& free, const Eigen::MatrixXd& b, double delta,
              double tolerance, int maxIterations, const detail::Tick& tick, Eigen::MatrixXd& x) {
  const Index c = D.rows(), m = D.cols();
  std::vector<Index> rowsF;  // samples with a free pair
  for (Index i = 0; i < c; ++i)
    if (free.row(i).any()) rowsF.push_back(i);
  const Index cf = Index(rowsF.size());
  x = Eigen::MatrixXd::Zero(c, m);
  if (cf == 0) return 0;
  // The problem on the rows with free pairs only: Kq(rowsF, rowsF).
  Eigen::MatrixXd Kf(cf, cf), Pm(m, m), mask(cf, m), bf(cf, m);
  for (Index a = 0; a < cf; ++a) {
    for (Index b2 = 0; b2 < cf; ++b2) Kf(a, b2) = D.kq(rowsF[std::size_t(a)], rowsF[std::size_t(b2)]);
    for (Index col = 0; col < m; ++col) mask(a, col) = free(rowsF[std::size_t(a)], col) ? 1.0 : 0.0;
    bf.row(a) = b.row(rowsF[std::size_t(a)]).cwiseProduct(mask.row(a));
  }
  for (Index e = 0; e < m; ++e)
    for (Index f = 0; f < m; ++f) Pm(e, f) = D.p(e, f);
  auto apply = [&](const Eigen::MatrixXd& v) -> Eigen::MatrixXd { return (Kf * (v * Pm)).cwiseProduct(mask) + delta * v; };
  std::vector<Eigen::LDLT<Eigen::MatrixXd>> blocks(static_cast<std::size_t>(cf));
  std::vector<std::vector<Index>> cols(static_cast<std::size_t>(cf));
  for (Index a = 0; a < cf; ++a) {
    auto& cs = cols[std::size_t(a)];
    for (Index col = 0; col < m; ++col)
      if (mask(a, col) != 0.0) cs.push_back(col);
    Eigen::MatrixXd B(Index(cs.size()), Index(cs.size()));
    for (std::size_t e = 0; e < cs.size(); ++e)
      for (std::size_t f = 0; f < cs.size(); ++f) B(Index(e), Index(f)) = Kf(a, a) * Pm(cs[e], cs[f]) + (e == f ? delta : 0.0);
    blocks[std::size_t(a)].compute(B);
  }
  auto precondition = [&](const Eigen::MatrixXd& r) {
    Eigen::MatrixXd z = Eigen::MatrixXd::Zero(cf, m);
    for (Index a = 0; a < cf; ++a) {
      const auto& cs = cols[std::size_t(a)];
      Eigen::VectorXd v(Index(cs.size()));
      for (std::size_t e = 0; e < cs.size(); ++e) v(Index(e)) = r(a, cs[e]);
      v = blocks[std::size_t(a)].solve(v);
      for (std::size_t e = 0; e < cs.size(); ++e) z(a, cs[e]) = v(Index(e));
    }
    return z;
  };
  Eigen::MatrixXd xf = Eigen::MatrixXd::Zero(cf, m), r = bf, z = precondition(r), dir = z;
  double rz = r.cwiseProduct(z).sum();
  int it = 0;
  while (it < maxIterations && r.cwiseAbs().maxCoeff() > tolerance) {
    ++it;
    const Eigen::MatrixXd q = apply(dir);
    const double dq = dir.cwiseProduct(q).sum();
    if (!(dq > 0.0)) break;
    const double alpha = rz / dq;
    xf += alpha * dir;
    r -= alpha * q;
    z = precondition(r);
    const double rzNew = r.cwiseProduct(z).sum();
    dir = z + (rzNew / rz) * dir;
    rz = rzNew;
    if (it % 2 == 0) tick();
  }
  for (Index a = 0; a < cf; ++a) x.row(rowsF[std::size_t(a)]) = xf.row(a);
  return it;
}

/// Kq = Kc (2H)⁻¹_A Kcᵀ on a growing list of constrained rows (the working rows, docs/rigidity.md):
/// only rows the dual needs get their columns. Dense: W = L⁻¹ Kc(rows)ᵀ is kept and a new block
/// costs a triangular solve and products with the kept W; sparse (CHOLMOD): F = (2H)⁻¹_A Kc(new)ᵀ
/// in chunks and Kq(rows, new) = Kc(rows) F.
class WorkingGram {
 public:
  WorkingGram(const SparseMatrix& Kc, const detail::DenseConstrainedSolve* dense, const ConstrainedSolve* sparse, const detail::Tick& tick)
      : m_Kc(Kc), m_dense(dense), m_sparse(sparse), m_tick(tick) {}
  /// Appends `rows` (not yet in the list) and extends Kq by their rows and columns.
  void add(const std::vector<Index>& rows) {
    const Index co = Index(m_rows.size()), cn = Index(rows.size());
    m_rows.insert(m_rows.end(), rows.begin(), rows.end());
    Eigen::MatrixXd Kon, Knn;  // Kq(old, new), Kq(new, new)
    if (m_dense) {
      Eigen::MatrixXd Wn = m_dense->halfSolve(subRows(rows), m_tick);
      Knn = m_dense->gram(Wn, m_tick);
      if (co == 0) {  // the first rows: no copies of the (large) blocks
        m_W = std::move(Wn);
        m_Kq = std::move(Knn);
        return;
      }
      Kon = m_dense->cross(m_W, Wn);
      m_W.conservativeResize(Wn.rows(), co + cn);
      m_W.rightCols(cn) = Wn;
    } else {
      const SparseMatrix KcAll = subRows(m_rows);
      const Eigen::MatrixXd KnT = Eigen::MatrixXd(SparseMatrix(subRows(rows).transpose()));
      Eigen::MatrixXd Kan(co + cn, cn);  // Kq(all, new)
      constexpr Index kChunk = 128;
      for (Index j = 0; j < cn; j += kChunk) {
        const Index w = std::min(kChunk, cn - j);
        Kan.middleCols(j, w) = KcAll * m_sparse->solve(KnT.middleCols(j, w));
        m_tick();
      }
      Kon = Kan.topRows(co);
      Knn = 0.5 * (Kan.bottomRows(cn) + Kan.bottomRows(cn).transpose());
    }
    m_Kq.conservativeResize(co + cn, co + cn);
    if (co > 0) {
      m_Kq.topRightCorner(co, cn) = Kon;
      m_Kq.bottomLeftCorner(cn, co) = Kon.transpose();
    }
    m_Kq.bottomRightCorner(cn, cn) = Knn;
  }
  const std::vector<Index>& rows() const { return m_rows; }
  const Eigen::MatrixXd& Kq() const { return m_Kq; }
  /// Kc's rows of the working list (|rows|×n).
  SparseMatrix working() const { return subRows(m_rows); }

 private:
  SparseMatrix subRows(const std::vector<Index>& rows) const {
    std::vector<Eigen::Triplet<double>> t;
    for (std::size_t a = 0; a < rows.size(); ++a)
      for (SparseRowMatrix::InnerIterator it(m_Kc, rows[a]); it; ++it) t.emplace_back(Index(a), it.col(), it.value());
    SparseMatrix K(Index(rows.size()), m_Kc.cols());
    K.setFromTriplets(t.begin(), t.end());
    return K;
  }

  SparseRowMatrix m_Kc;
  const detail::DenseConstrainedSolve* m_dense;
  const ConstrainedSolve* m_sparse;
  const detail::Tick& m_tick;
  std::vector<Index> m_rows;
  Eigen::MatrixXd m_W, m_Kq;
};

/// Eigen's own products on the calling thread while it lives (the OpenMP thread count of this thread
/// only; BLAS keeps its threads). The active set's Eigen products are small (Q Λ = Kq Λ P is ~5 MFlop
/// per round on a 500-sample region): split over two threads, each waits for the other to be
/// scheduled, and with the machine's other cores busy that made the star's 500-sample release about
/// 2.5× slower (510–570 ms against 190–200 ms with this guard, load 5–6 on 2 cores; docs/rigidity.md).
class SerialEigen {
 public:
  SerialEigen() : m_before(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~SerialEigen() { omp_set_num_threads(m_before); }
  SerialEigen(const SerialEigen&) = delete;
  SerialEigen& operator=(const SerialEigen&) = delete;

 private:
  int m_before;
};

/// What pivot() did: `inner` rounds; `settled`: no infeasible pair was left; `failed`: Q_AA + εI
/// could not be factorized.
struct Pivoting {
  bool failed = false, settled = false;
  int inner = 0;
};

/// One proximal step's problem: min d(Λ) + ε/2 ‖Λ − Mu‖² over Λ ≥ 0, a linear complementarity
/// problem with the positive definite Q + εI, by block principal pivoting (Júdice & Pires 1994):
/// exchange every infeasible pair (the primal-dual active set step) while their number falls,
/// else (after 3 tries) only one (Murty's rule, finite for positive definite matrices). At most 25
/// rounds, and `rounds` (all of the solve's) stays within options.maxActiveSetRounds. `active`:
/// the free pairs w·m + k, updated; Lambda (working rows × m) the multipliers of the last round.
Pivoting pivot(const BoundDual& D, detail::PairSystem& pairs, const Eigen::MatrixXd& Mu, double eps, double scale,
               const RigidityQpOptions& options, std::vector<Index>& active, Eigen::MatrixXd& Lambda, int& rounds,
               RigidityQpReport& rep, double& stage, const detail::Tick& tick) {
  const Index cw = Lambda.rows(), m = Lambda.cols();
  const double tol = options.tolerance;
  Eigen::Matrix<char, Eigen::Dynamic, Eigen::Dynamic> free(cw, m);
  Eigen::VectorXd rhs, lambda;
  Eigen::MatrixXd QL, g;
  pairs.setShift(eps);  // a new ε: Q_AA + εI factorized again
  Index fewest = std::numeric_limits<Index>::max();
  int backup = 3;
  Pivoting out;
  for (; out.inner < 25 && rounds < options.maxActiveSetRounds; ++out.inner) {
    ++rounds;
    stage = std::max(stage, 0.4 + 0.55 * double(rounds) / options.maxActiveSetRounds);
    const Index a = Index(active.size());
    Lambda.setZero();
    free.setZero();
    for (Index p : active) free(p / m, p % m) = 1;
    if (a > 0 && a <= options.maxDensePairs) {  // Q_AA + εI: updated as pairs enter and leave (detail::PairSystem)
      rhs.resize(a);
      for (Index p = 0; p < a; ++p) {
        const Index w = active[std::size_t(p)] / m, k = active[std::size_t(p)] % m;
        rhs(p) = D.R()(w, k) + eps * Mu(w, k);
      }
      if (!pairs.solve(active, rhs, lambda)) {
        out.failed = true;
        return out;
      }
      for (Index p = 0; p < a; ++p) Lambda(active[std::size_t(p)] / m, active[std::size_t(p)] % m) = lambda(p);
    } else if (a > 0) {  // too many pairs for a dense factorization: conjugate gradients on Q_AA + εI
      rep.cgIterations += solveFree(D, free, D.R() + eps * Mu, eps, 1e-3 * tol, options.maxCgIterations, tick, Lambda);
    }
    QL = D.apply(Lambda);
    g = QL - D.R() + eps * (Lambda - Mu);  // the inner problem's gradient
    std::vector<Index> infeasible;
    for (Index w = 0; w < cw; ++w)
      for (Index k = 0; k < m; ++k)
        if (free(w, k) ? scale * Lambda(w, k) < -1e-3 * tol : g(w, k) < -1e-3 * tol) infeasible.push_back(w * m + k);
    tick();
    if (infeasible.empty()) {
      out.settled = true;
      break;
    }
    if (Index(infeasible.size()) < fewest) {
      fewest = Index(infeasible.size());
      backup = 3;
    } else if (backup > 0) {
      --backup;
    } else {
      infeasible.erase(infeasible.begin(), infeasible.end() - 1);  // Murty: the last infeasible pair only
    }
    for (Index p : infeasible) free(p / m, p % m) = !free(p / m, p % m);
    active.clear();
    for (Index w = 0; w < cw; ++w)
      for (Index k = 0; k < m; ++k)
        if (free(w, k)) active.push_back(w * m + k);
  }
  return out;
}

/// The bounds' dual d(Λ) over Λ ≥ 0 (BoundDual above) after one factorization of 2H with A
/// through its Schur complement, by proximal point steps (docs/rigidity.md): each step minimizes
/// d(Λ) + ε/2‖Λ − Λ_k‖², a linear complementarity problem with the positive definite Q + εI, by
/// block principal pivoting (Júdice & Pires 1994): the free pairs' multipliers from Q_AA + εI
/// (dense Cholesky updated as pairs enter and leave, detail::PairSystem; CG beyond maxDensePairs),
/// then every infeasible pair changes sides while their number falls, else only the last one
/// (Murty's rule, finite for positive definite matrices; the plain primal-dual active set cycled on
/// soft brush strokes, where the bound pairs are degenerate and Q_AA singular). A step that does
/// not settle in 25 rounds makes ε ten times larger. It stops when max |min(s·Λ, slack)| ≤
/// tolerance (weights; s = the mean diagonal of Q): the bounds hold to the tolerance and pairs with
/// a positive multiplier are at their bounds. The dual is taken over working rows only — those the
/// equality-constrained optimum Y0 violates, then those the primal of the dual's solution violates
/// — so that Kq's columns are formed only for rows that may bind. Returns false when it does not
/// converge within maxActiveSetRounds (the caller falls back to the splitting path); throws
/// kc::Cancelled when options.progress asks to stop.
bool solveActiveSet(const RigidityQp& qp, const RigidityQpOptions& options, RigidityQpReport& rep, RowMatrix& dU) {
  const SerialEigen serial;
  const Index n = qp.H.rows(), c = qp.Kc.rows();
  double stage = 0.0;  // the share reported between blocks of dense work
  const detail::Tick tick = detail::progressTick(options.progress, stage);
  // M = 2H + a tiny diagonal shift (definite where H is only semi-definite).
  const double shift = 1e-13 * std::max(2.0 * qp.H.diagonal().sum() / double(n), 1e-300);
  const auto tf = std::chrono::steady_clock::now();
  // (2H)⁻¹_A: a dense factorization up to maxDenseNodes (Kq's blocks then cost a triangular solve
  // and products), CHOLMOD's sparse one beyond.
  const bool dense = n <= options.maxDenseNodes;
  detail::DenseConstrainedSolve denseSolver;
  ConstrainedSolve sparseSolver;
  if (dense) {
    if (!denseSolver.compute(qp.H, 2.0, shift, qp.A, options.rankTolerance, tick)) return false;
  } else {
    SparseMatrix M = 2.0 * qp.H, I(n, n);
    I.setIdentity();
    M += shift * I;
    M.makeCompressed();
    if (!sparseSolver.compute(M, qp.A, options.rankTolerance)) return false;
  }
  auto solveA = [&](const Eigen::MatrixXd& rhs) { return dense ? denseSolver.solve(rhs) : sparseSolver.solve(rhs); };
  rep.factorSeconds = secondsSince(tf);
  stage = 0.1;
  tick();
  const Eigen::MatrixXd Y0 = solveA(-2.0 * (qp.G * qp.Z));
  dU = Y0 * qp.Z.transpose();
  rep.converged = true;
  if (c == 0) return true;
  // The active controls (non-zero rows of Z): Z' (m'×r), P = Z'Z'ᵀ, and the slack of Y0 against
  // the bounds, Kc Y0 Z'ᵀ − L' (c×m').
  std::vector<Index> ctl;
  for (Index col = 0; col < qp.Z.rows(); ++col)
    if (qp.Z.row(col).squaredNorm() > 0.0) ctl.push_back(col);
  const Index m = Index(ctl.size());
  Eigen::MatrixXd Zs(m, qp.Z.cols()), Ls(c, m);
  for (Index k = 0; k < m; ++k) Zs.row(k) = qp.Z.row(ctl[std::size_t(k)]), Ls.col(k) = qp.L.col(ctl[std::size_t(k)]);
  const Eigen::MatrixXd P = Zs * Zs.transpose();
  const double tol = options.tolerance;
  auto violatedRows = [&](const Eigen::MatrixXd& Y, const std::vector<char>& in) {
    const Eigen::MatrixXd slack = (qp.Kc * Y) * Zs.transpose() - Ls;
    std::vector<Index> rows;
    for (Index i = 0; i < c; ++i)
      if (!in[std::size_t(i)] && slack.row(i).minCoeff() < -tol) rows.push_back(i);
    return rows;
  };
  std::vector<char> working(std::size_t(c), 0);
  std::vector<Index> add = violatedRows(Y0, working);
  if (add.empty()) return true;  // Y0 keeps every bound
  rep.converged = false;
  const Eigen::MatrixXd S0 = (qp.Kc * Y0) * Zs.transpose();
  WorkingGram gram(qp.Kc, dense ? &denseSolver : nullptr, dense ? nullptr : &sparseSolver, tick);

  Eigen::MatrixXd Lambda, Mu, QL;
  std::vector<Index> active;  // pairs (working row w, active control k) as w·m + k, ascending
  double scale = 0.0, epsRel = options.proximal, first = 0.0;
  int rounds = 0;
  bool done = false;
  while (!add.empty()) {  // a working set: the dual over its rows, then the rows its primal violates
    stage = std::max(stage, 0.1 + 0.3 * double(gram.rows().size() + add.size()) / double(c));
    for (Index i : add) working[std::size_t(i)] = 1;
    gram.add(add);
    rep.workingRows = Index(gram.rows().size());
    ++rep.workingSets;
    const std::vector<Index>& rows = gram.rows();
    const Index cw = Index(rows.size()), co = Lambda.rows();
    Eigen::MatrixXd R(cw, m);
    for (Index w = 0; w < cw; ++w) R.row(w) = Ls.row(rows[std::size_t(w)]) - S0.row(rows[std::size_t(w)]);
    const BoundDual D(gram.Kq(), P, std::move(R));
    Lambda.conservativeResize(cw, m);
    Lambda.bottomRows(cw - co).setZero();
    Mu = Lambda;
    if (scale == 0.0) {  // mean diagonal of Q on the first working rows: multipliers times this are in weight units
      for (Index w = 0; w < cw; ++w)
        for (Index k = 0; k < m; ++k) scale += D.diagonal(w, k);
      scale = std::max(scale / double(cw * m), 1e-300);
    }
    for (Index w = co; w < cw; ++w)
      for (Index k = 0; k < m; ++k)
        if (D.R()(w, k) > tol) active.push_back(w * m + k);
    std::sort(active.begin(), active.end());
    detail::PairSystem pairs(D.Kq(), D.P(), epsRel * scale, tick);
    done = false;
    while (!done && rounds < options.maxActiveSetRounds) {
      // Inner: the proximal step's complementarity problem (pivot).
      const Pivoting pv = pivot(D, pairs, Mu, epsRel * scale, scale, options, active, Lambda, rounds, rep, stage, tick);
      if (pv.failed) return false;
      // Not settled in 25 rounds: a larger ε (Q + εI nearer a diagonal, on which the exchanges settle);
      // settled at once: back toward the default (smaller ε, faster proximal steps).
      if (!pv.settled) epsRel = std::min(10.0 * epsRel, 1.0);
      else if (pv.inner <= 1) epsRel = std::max(0.1 * epsRel, options.proximal);
      // Outer (proximal point): the unregularized KKT residual at the clamped multipliers.
      Lambda = Lambda.cwiseMax(0.0);
      QL = D.apply(Lambda);
      const double residual = (scale * Lambda).cwiseMin(QL - D.R()).cwiseAbs().maxCoeff();
      if (first == 0.0) first = std::max(residual, 10.0 * tol);
      done = residual <= tol;
      Mu = Lambda;
      stage = std::max(stage, 0.4 + 0.55 * std::log(first / std::max(residual, tol)) / std::log(first / tol));
      tick();
    }
    if (!done) break;
    const Eigen::MatrixXd Y = Y0 + solveA(SparseMatrix(gram.working().transpose()) * (Lambda * Zs));
    dU = Y * qp.Z.transpose();
    add = violatedRows(Y, working);
  }
  rep.iterations = rounds;
  rep.converged = done;
  return done;
}

}  // namespace

RowMatrix solveRigidityQp(const RigidityQp& qp, const RigidityQpOptions& options, RigidityQpReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  RigidityQpReport local;
  RigidityQpReport& rep = report ? *report : local;
  rep = {};
  const Index n = qp.H.rows(), m = qp.G.cols(), r = qp.Z.cols(), c = qp.Kc.rows();
  if (qp.H.cols() != n || qp.G.rows() != n || qp.Z.rows() != m || (qp.A.rows() > 0 && qp.A.cols() != n) ||
      (c > 0 && (qp.Kc.cols() != n || qp.L.rows() != c || qp.L.cols() != m)))
    throw std::invalid_argument("solveRigidityQp: inconsistent shapes");
  if (n == 0 || r == 0) {
    rep.converged = true;
    return RowMatrix::Zero(n, m);
  }
  const Index pairs = c * Index(detail::RowPolytope(qp.Z).size());
  if (options.method == RigidityQpMethod::Splitting || pairs > options.largePairs) return detail::solveSplitting(qp, options, rep);
  RowMatrix dU;
  if (solveActiveSet(qp, options, rep, dU)) {
    rep.method = RigidityQpMethod::ActiveSet;
    const RowMatrix KdU = qp.Kc * dU;
    rep.violation = c > 0 ? std::max(0.0, (qp.L - KdU).maxCoeff()) : 0.0;
    rep.objective = rigidityObjective(qp, dU);
    rep.seconds = secondsSince(t0);
    return dU;
  }
  // Not settled (e.g. a nearly singular H): the splitting path gives a near-optimal answer in a
  // few hundred iterations at most, whose bounds the caller makes exact row by row.
  rep = {};
  return detail::solveSplitting(qp, options, rep);
}

}  // namespace kc
