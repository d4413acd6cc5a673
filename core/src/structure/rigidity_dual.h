#pragma once
// Private to kc::core: the dense linear algebra of the rigidity QP's bound dual (docs/rigidity.md,
// "The QP and its solver"): a blocked Cholesky factorization that reports between blocks, the
// equality-constrained solves with a dense factorization of 2H and the dual's Gram matrix
// Kq = Kc (2H)⁻¹_A Kcᵀ, and the solves with Q_AA + εI for active sets near a factorized one
// (a Schur complement update instead of a new factorization at every change of the set).

#include <Eigen/Dense>
#include <functional>
#include <iterator>
#include <memory>
#include <unordered_map>
#include <vector>

#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"
#include "../huge_pages.h"

namespace kc::detail {

/// Called between blocks of dense work (each a few milliseconds on a 2,000-row problem); it may
/// throw to stop the computation (the solver's Cancel).
using Tick = std::function<void()>;

/// The solvers' Tick: reports `stage` (read at each call, clamped to [0, 1]) to `progress` when it
/// is set, and throws kc::Cancelled when it returns false.
Tick progressTick(const Progress& progress, const double& stage);

/// A = L Lᵀ in place for a symmetric positive definite A (n×n; the lower triangle is read, L is
/// left in it), right-looking by panels of `block` columns (factor the diagonal block, solve the
/// panel below it, update the trailing block: LAPACK's dpotrf, BLAS's dtrsm and dsyrk, see
/// dense_blas.h), with tick() after each panel. Returns false when a pivot is not positive (A is
/// then partly overwritten).
bool blockedCholesky(Eigen::Ref<Eigen::MatrixXd> A, const Tick& tick, Index block = 192);

/// The pseudo-inverse of a symmetric S (a×a): its eigenvalues below rankTolerance × the largest
/// magnitude are treated as zero.
Eigen::MatrixXd symmetricPseudoInverse(const Eigen::MatrixXd& S, double rankTolerance);

/// The equality-constrained solve M⁻¹_A b = argmin_{A y = 0} ½ yᵀ M y − bᵀ y for a symmetric
/// positive definite M (n×n) and equality rows A (a×n), on a dense Cholesky factorization M = L Lᵀ:
///   M⁻¹_A = M⁻¹ − M⁻¹Aᵀ S⁺ A M⁻¹ = L⁻ᵀ (I − V S⁺ Vᵀ) L⁻¹,   V = L⁻¹ Aᵀ (n×a),  S = Vᵀ V
/// (S's pseudo-inverse: held samples close together make it nearly singular).
class DenseConstrainedSolve {
 public:
  /// Factorizes M = scale·H + shift·I (a dense copy of its lower triangle; L's upper triangle is
  /// left unset) and forms V and S⁺; false when M is not positive definite.
  bool compute(const SparseMatrix& H, double scale, double shift, const RowMatrix& A, double rankTolerance, const Tick& tick);
  /// M⁻¹_A rhs for rhs n×k.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const;
  /// W = L⁻¹ Kcᵀ (n×c) for rows Kc (c×n), by blocks of 128 columns with tick() between them.
  Eigen::MatrixXd halfSolve(const SparseMatrix& Kc, const Tick& tick) const;
  /// Kc1 M⁻¹_A Kc2ᵀ = W1ᵀ W2 − T1ᵀ S⁺ T2 (c1×c2) from W1 = L⁻¹Kc1ᵀ, W2 = L⁻¹Kc2ᵀ (T = Vᵀ W).
  Eigen::MatrixXd cross(const Eigen::MatrixXd& W1, const Eigen::MatrixXd& W2) const;
  /// The symmetric Kc M⁻¹_A Kcᵀ (c×c) from W = L⁻¹Kcᵀ: a symmetric rank update by blocks of W's
  /// rows (tick() between them) instead of cross(W, W)'s full product.
  Eigen::MatrixXd gram(const Eigen::MatrixXd& W, const Tick& tick) const;

 private:
  Eigen::MatrixXd m_L, m_V, m_Splus;
};

/// Solves (Q_AA + εI) x = b for sets A of pairs near a factorized base set B, where the dual's
/// Hessian is Q = Kq ⊗ P (pair p = (row i, control k) = i·m + k, Q(p, q) = Kq(i_p, i_q) P(k_p, k_q)).
/// With D = A \ B (pairs added since B was factorized) and E = B \ A (pairs removed), x is the
/// solution of the bordered system over B ∪ D in which x_E = 0 is imposed with multipliers μ:
///   [Q_BB  Q_BD  I_E] [x_B]   [b_B]
///   [Q_DB  Q_DD  0  ] [x_D] = [b_D]        (Q with εI on its diagonal; b_E = 0),
///   [I_Eᵀ  0     0  ] [μ  ]   [0  ]
/// solved through the Schur complement of Q_BB: with U = [Q_BD I_E] and X = Q_BB⁻¹ U (its columns
/// kept while B stays, so a pair that stays in D or E costs nothing in later rounds),
///   S = [Q_DD 0; 0 0] − Uᵀ X  (s×s, s = |D| + |E|),   S y = [b_D; 0] − Xᵀ b_B,   x_B = Q_BB⁻¹ b_B − X y.
/// B is factorized again (B = A) when s exceeds max(minUpdate, |B|/8): beyond that the update
/// costs more than the factorization (2|B|²s + |B|s² against |B|³/3).
class PairSystem {
 public:
  /// Kq (c×c) and P (m×m) are referenced, not copied; ε is the proximal shift on the diagonal.
  PairSystem(const Eigen::MatrixXd& Kq, const Eigen::MatrixXd& P, double eps, Tick tick);
  /// A new ε: the next solve factorizes again.
  void setShift(double eps);
  /// x (|A|) with (Q_AA + εI) x = b (|A|) for `set` (pair indices, ascending). Returns false when
  /// a factorization of Q_BB + εI fails (not positive definite in floating point).
  bool solve(const std::vector<Index>& set, const Eigen::VectorXd& b, Eigen::VectorXd& x);
  int factorizations() const { return m_factorizations; }

 private:
  static constexpr std::size_t kMinUpdate = 32;  // changes always handled by the update
  /// out(a, b) = Q(rows[a], cols[b]) (+ ε where the pairs are equal), out sized |rows|×|cols|; with
  /// `lower` (rows = cols) only a ≥ b is written (the upper triangle is left unset and untouched).
  void fill(const std::vector<Index>& rows, const std::vector<Index>& cols, Eigen::Ref<Eigen::MatrixXd> out, bool lower = false) const;
  /// The factor of Q_BB + εI (|B|×|B|, column-major) in m_store.
  Eigen::Map<Eigen::MatrixXd> base() { return {m_store.get(), Index(m_base.size()), Index(m_base.size())}; }
  bool factorize(const std::vector<Index>& set);
  /// Q_BB⁻¹ u into m_columns for the pairs not there yet: u = Q(B, p) for p ∉ B (added), u = e_p for
  /// p ∈ B (removed); one solve with all of them as columns.
  void addColumns(const std::vector<Index>& pairs);
  /// v ← Q_BB⁻¹ v (two triangular solves with the base factor).
  void solveBase(Eigen::Ref<Eigen::MatrixXd> v) const;

  const Eigen::MatrixXd& m_Kq;
  const Eigen::MatrixXd& m_P;
  double m_eps;
  Tick m_tick;
  std::vector<Index> m_base;                  // B (ascending)
  std::unordered_map<Index, Index> m_pos;     // pair → position in B
  HugeArray m_store;                          // Q_BB + εI = L Lᵀ (L in the lower triangle); grows only: fresh
  Index m_capacity = 0;                       // memory costs page faults (huge pages: fewer), and a smaller set reuses it
  std::unordered_map<Index, Eigen::VectorXd> m_columns;  // X's columns by pair
  bool m_factored = false;
  int m_factorizations = 0;
};

}  // namespace kc::detail
