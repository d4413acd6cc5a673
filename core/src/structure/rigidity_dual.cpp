#include "rigidity_dual.h"

#include <algorithm>

#include "../dense_blas.h"
#include "kc/core/structure/rigidity_qp.h"

namespace kc::detail {

Tick progressTick(const Progress& progress, const double& stage) {
  return [&progress, &stage] {
    if (progress && !progress(std::clamp(stage, 0.0, 1.0))) throw Cancelled();
  };
}

bool blockedCholesky(Eigen::Ref<Eigen::MatrixXd> A, const Tick& tick, Index block) {
  const Index n = A.rows();
  for (Index k = 0; k < n; k += block) {
    const Index b = std::min(block, n - k), rest = n - k - b;
    auto A11 = A.block(k, k, b, b);
    if (!blas::cholesky(A11)) return false;  // L11 in A11's lower triangle
    if (rest > 0) {
      auto A21 = A.block(k + b, k, rest, b);
      blas::solveLowerTransposeRight(A11, A21);                           // L21 = A21 L11⁻ᵀ
      blas::rankUpdateLower(A.block(k + b, k + b, rest, rest), A21, -1.0, 1.0);  // A22 −= L21 L21ᵀ
    }
    if (tick) tick();
  }
  return true;
}

Eigen::MatrixXd symmetricPseudoInverse(const Eigen::MatrixXd& S, double rankTolerance) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (S + S.transpose()));
  const Eigen::VectorXd& d = eig.eigenvalues();
  const double cut = rankTolerance * std::max(d.cwiseAbs().maxCoeff(), 1e-300);
  Eigen::VectorXd inv(d.size());
  for (Index k = 0; k < d.size(); ++k) inv(k) = d(k) > cut ? 1.0 / d(k) : 0.0;
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}

bool DenseConstrainedSolve::compute(const SparseMatrix& H, double scale, double shift, const RowMatrix& A, double rankTolerance,
                                    const Tick& tick) {
  // The lower triangle of M = scale·H + shift·I only: the factorization and the solves read nothing
  // else, and the upper half's memory is never touched (fresh pages cost faults).
  const Index n = H.rows();
  m_L.resize(n, n);
  preferHugePages(m_L);
  for (Index j = 0; j < n; ++j) {
    m_L.col(j).tail(n - j).setZero();
    for (SparseMatrix::InnerIterator it(H, j); it; ++it)
      if (it.row() >= j) m_L(it.row(), j) = scale * it.value();
    m_L(j, j) += shift;
  }
  if (!blockedCholesky(m_L, tick)) return false;
  m_V.resize(n, 0);
  m_Splus.resize(0, 0);
  if (A.rows() == 0) return true;
  m_V = A.transpose();
  blas::solveLower(m_L, m_V);
  m_Splus = symmetricPseudoInverse(m_V.transpose() * m_V, rankTolerance);
  return true;
}

Eigen::MatrixXd DenseConstrainedSolve::solve(const Eigen::MatrixXd& rhs) const {
  Eigen::MatrixXd w = rhs;
  blas::solveLower(m_L, w);
  if (m_V.cols() > 0) w -= m_V * (m_Splus * (m_V.transpose() * w));
  blas::solveLower(m_L, w, true);
  return w;
}

Eigen::MatrixXd DenseConstrainedSolve::halfSolve(const SparseMatrix& Kc, const Tick& tick) const {
  const Index c = Kc.rows();
  constexpr Index kBlock = 128;
  Eigen::MatrixXd W(Kc.cols(), c);  // n×c: Kcᵀ, dense
  preferHugePages(W);
  W.setZero();
  for (Index j = 0; j < Kc.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(Kc, j); it; ++it) W(j, it.row()) = it.value();
  for (Index j = 0; j < c; j += kBlock) {
    blas::solveLower(m_L, W.middleCols(j, std::min(kBlock, c - j)));
    if (tick) tick();
  }
  return W;
}

Eigen::MatrixXd DenseConstrainedSolve::cross(const Eigen::MatrixXd& W1, const Eigen::MatrixXd& W2) const {
  Eigen::MatrixXd K(W1.cols(), W2.cols());
  blas::multiply(K, W1, true, W2, false);
  if (m_V.cols() > 0) K -= (m_V.transpose() * W1).transpose() * (m_Splus * (m_V.transpose() * W2));
  return K;
}

Eigen::MatrixXd DenseConstrainedSolve::gram(const Eigen::MatrixXd& W, const Tick& tick) const {
  const Index n = W.rows(), c = W.cols();
  constexpr Index kBlock = 128;
  Eigen::MatrixXd K(c, c);
  preferHugePages(K);
  for (Index j = 0; j < c; ++j) K.col(j).tail(c - j).setZero();
  for (Index i = 0; i < n; i += kBlock) {  // K += W_iᵀ W_i over blocks of W's rows
    blas::rankUpdateLower(K, W.middleRows(i, std::min(kBlock, n - i)), 1.0, 1.0, true);
    if (tick) tick();
  }
  K.triangularView<Eigen::StrictlyUpper>() = K.transpose();
  if (m_V.cols() > 0) {
    const Eigen::MatrixXd T = m_V.transpose() * W;  // a×c
    K -= T.transpose() * (m_Splus * T);
  }
  return K;
}

PairSystem::PairSystem(const Eigen::MatrixXd& Kq, const Eigen::MatrixXd& P, double eps, Tick tick)
    : m_Kq(Kq), m_P(P), m_eps(eps), m_tick(std::move(tick)) {}

void PairSystem::setShift(double eps) {
  if (eps != m_eps) m_factored = false;
  m_eps = eps;
}

void PairSystem::fill(const std::vector<Index>& rows, const std::vector<Index>& cols, Eigen::Ref<Eigen::MatrixXd> out, bool lower) const {
  const Index m = m_P.rows(), nr = Index(rows.size());
  std::vector<Index> ri(rows.size()), ki(rows.size());
  for (std::size_t a = 0; a < rows.size(); ++a) ri[a] = rows[a] / m, ki[a] = rows[a] % m;
  for (std::size_t b = 0; b < cols.size(); ++b) {
    const Index j = cols[b] / m, l = cols[b] % m;
    const double* kq = m_Kq.col(j).data();
    const double* p = m_P.col(l).data();
    double* o = out.col(Index(b)).data();
    for (Index a = lower ? Index(b) : 0; a < nr; ++a) o[a] = kq[ri[std::size_t(a)]] * p[ki[std::size_t(a)]];
    if (const auto at = std::lower_bound(rows.begin(), rows.end(), cols[b]); at != rows.end() && *at == cols[b])
      o[at - rows.begin()] += m_eps;
  }
}

bool PairSystem::factorize(const std::vector<Index>& set) {
  m_base = set;
  m_pos.clear();
  for (std::size_t a = 0; a < set.size(); ++a) m_pos.emplace(set[a], Index(a));
  m_columns.clear();
  const Index nb = Index(set.size());
  if (m_capacity < nb * nb) {  // kept: a smaller set reuses the memory (left uninitialized: fill writes what is read)
    m_store = allocateHuge(std::size_t(nb * nb));
    m_capacity = nb * nb;
  }
  fill(m_base, m_base, base(), true);  // the factorization reads the lower triangle only
  ++m_factorizations;
  m_factored = blockedCholesky(base(), m_tick);
  return m_factored;
}

void PairSystem::solveBase(Eigen::Ref<Eigen::MatrixXd> v) const {
  const Eigen::Map<const Eigen::MatrixXd> L(m_store.get(), Index(m_base.size()), Index(m_base.size()));
  blas::solveLower(L, v);
  blas::solveLower(L, v, true);
}

void PairSystem::addColumns(const std::vector<Index>& pairs) {
  std::vector<Index> added, missing;
  for (Index p : pairs)
    if (!m_columns.count(p)) (m_pos.count(p) ? missing : added).push_back(p);
  const Index nb = Index(m_base.size()), na = Index(added.size());
  if (added.empty() && missing.empty()) return;
  Eigen::MatrixXd U(nb, na + Index(missing.size()));  // [Q(B, added) e_removed]: one multi-column solve
  if (na > 0) {
    Eigen::MatrixXd QBD(nb, na);
    fill(m_base, added, QBD);
    U.leftCols(na) = QBD;
  }
  U.rightCols(Index(missing.size())).setZero();
  for (std::size_t j = 0; j < missing.size(); ++j) U(m_pos.at(missing[j]), na + Index(j)) = 1.0;
  solveBase(U);
  for (Index j = 0; j < na; ++j) m_columns.emplace(added[std::size_t(j)], U.col(j));
  for (std::size_t j = 0; j < missing.size(); ++j) m_columns.emplace(missing[j], U.col(na + Index(j)));
  if (m_tick) m_tick();
}

bool PairSystem::solve(const std::vector<Index>& set, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  x.resize(Index(set.size()));
  if (set.empty()) return true;
  std::vector<Index> added, removed;
  if (m_factored) {
    std::set_difference(set.begin(), set.end(), m_base.begin(), m_base.end(), std::back_inserter(added));
    std::set_difference(m_base.begin(), m_base.end(), set.begin(), set.end(), std::back_inserter(removed));
  }
  const std::size_t s = added.size() + removed.size();
  if (!m_factored || s > std::max<std::size_t>(kMinUpdate, m_base.size() / 8)) {
    if (!factorize(set)) return false;
    added.clear(), removed.clear();
  }
  const Index nb = Index(m_base.size());
  Eigen::VectorXd bB = Eigen::VectorXd::Zero(nb), bD(Index(added.size()));
  for (std::size_t a = 0, d = 0; a < set.size(); ++a) {
    if (auto at = m_pos.find(set[a]); at != m_pos.end()) bB(at->second) = b(Index(a));
    else bD(Index(d++)) = b(Index(a));
  }
  Eigen::VectorXd xB = bB;
  solveBase(xB);
  if (added.empty() && removed.empty()) {
    for (std::size_t a = 0; a < set.size(); ++a) x(Index(a)) = xB(m_pos.at(set[a]));
    return true;
  }
  const Index nd = Index(added.size()), ne = Index(removed.size()), ns = nd + ne;
  addColumns(added);
  addColumns(removed);
  Eigen::MatrixXd X(nb, ns);
  for (Index j = 0; j < nd; ++j) X.col(j) = m_columns.at(added[std::size_t(j)]);
  for (Index j = 0; j < ne; ++j) X.col(nd + j) = m_columns.at(removed[std::size_t(j)]);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(ns, ns), QBD, QDD;
  if (nd > 0) {
    QBD.resize(nb, nd);
    QDD.resize(nd, nd);
    fill(m_base, added, QBD);
    fill(added, added, QDD);
    S.topLeftCorner(nd, nd) = QDD - QBD.transpose() * X.leftCols(nd);
  }
  for (Index j = 0; j < ne; ++j) {  // Uᵀ X against a removed pair e: e_eᵀ X = X's row e
    const Index e = m_pos.at(removed[std::size_t(j)]);
    S.row(nd + j) = -X.row(e);
    S.col(nd + j) = -X.row(e).transpose();
  }
  Eigen::VectorXd rhs(ns);
  rhs.head(nd) = bD - X.leftCols(nd).transpose() * bB;
  for (Index j = 0; j < ne; ++j) rhs(nd + j) = -xB(m_pos.at(removed[std::size_t(j)]));
  const Eigen::VectorXd y = S.partialPivLu().solve(rhs);
  xB -= X * y;
  for (std::size_t a = 0, d = 0; a < set.size(); ++a) {
    if (auto at = m_pos.find(set[a]); at != m_pos.end()) x(Index(a)) = xB(at->second);
    else x(Index(a)) = y(Index(d++));
  }
  return true;
}

}  // namespace kc::detail
