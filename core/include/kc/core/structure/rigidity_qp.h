#pragma once
/// The joint sparse QP of a rigid region (docs/rigidity.md; thesis 5.35 rewritten for the exact
/// interpolation): the change ΔU of the kernel coefficients of the nodes near the region,
///   min_ΔU  tr(ΔUᵀ H ΔU) + 2 tr(ΔUᵀ G)
///   s.t.    ΔU = Y Zᵀ            (every row of ΔU in span Z: partition of unity and reproduction)
///           A ΔU = 0             (held samples unchanged: their rows K(h, N), scaled to unit length)
///           Kc ΔU ≥ L            (non-negativity of the constrained samples' weights)
/// solved on the bounds' dual (one factorization of 2H, dense up to maxDenseNodes; the dual's
/// matrix Kq ⊗ P with Kq = Kc (2H)⁻¹_A Kcᵀ; proximal point steps, each by block principal pivoting
/// with Q_AA + εI's factorization updated as pairs enter and leave); beyond largePairs bound
/// pairs, or when the dual method does not settle, by ADMM (Boyd et al. 2011, §3; OSQP's
/// splitting) on one factorization of 2H + μ KcᵀKc shared by all columns of Y, its split variable
/// projected onto each row's polytope, accelerated, to a moderate tolerance
/// (RigidityQpMethod::Splitting; docs/rigidity.md, "Large regions").

#include <exception>
#include <functional>

#include "kc/core/solve.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc {

/// One rigidity QP over n nodes, m controls, c constrained samples and a equality rows.
struct RigidityQp {
  SparseMatrix H;   ///< n×n symmetric positive semi-definite (positive definite on A's null space).
  RowMatrix G;      ///< n×m linear term.
  RowMatrix Z;      ///< m×r orthonormal columns: ΔU = Y Zᵀ (r ≥ 1).
  RowMatrix A;      ///< a×n equality rows A ΔU = 0 (may be empty).
  SparseMatrix Kc;  ///< c×n constraint operator (may be empty).
  RowMatrix L;      ///< c×m lower bounds of Kc ΔU, ≤ 0 (ΔU = 0 is feasible).
};

/// How the QP is solved: the bounds' active set, found on their dual (one factorization of 2H;
/// beyond largePairs bound pairs, or when it does not settle, the splitting path), or the
/// splitting path throughout: ADMM with the split variable projected onto each constrained
/// sample's row polytope, to splittingTolerance (the caller projects the rows of the stored
/// weights: detail::projectRows, docs/rigidity.md, "Large regions").
enum class RigidityQpMethod { ActiveSet, Splitting };

struct RigidityQpOptions {
  RigidityQpMethod method = RigidityQpMethod::ActiveSet;
  int maxActiveSetRounds = 500;  ///< Active-set rounds (all proximal steps together) before falling back to the splitting path.
  double proximal = 1e-3;        ///< ε of the proximal term ε/2‖Λ − Λ_k‖², relative to the mean diagonal of the dual's Q (grows tenfold when a step does not settle).
  Index maxDensePairs = 4000;    ///< Active pairs up to which Q_AA + εI is factorized (dense); beyond, conjugate gradients.
  Index maxDenseNodes = 3000;    ///< Nodes up to which 2H is factorized dense (Kq by a triangular solve and a rank update); beyond, CHOLMOD.
  int maxCgIterations = 2000;    ///< Conjugate-gradient iterations per round beyond maxDensePairs.
  double tolerance = 1e-8;       ///< Active set: stop when max |min(s Λ, slack)| ≤ tolerance (weights; docs/rigidity.md).
  double penalty = 0.0;          ///< Splitting: the initial ADMM penalty μ; ≤ 0: trace(2H) / trace(KcᵀKc).
  double relaxation = 1.6;       ///< Splitting: over-relaxation α ∈ (0, 2).
  Index largePairs = 20000;       ///< ActiveSet: beyond this many bound pairs (constrained rows × active controls), Splitting.
  double splittingTolerance = 1e-4;      ///< Splitting: largest violation of a bound (weights) at the stop,
  double splittingDualTolerance = 1e-3;  ///< and the dual residual relative to max|2 G Z|.
  int splittingIterations = 300;         ///< Splitting: iterations before it returns the last iterate (converged = false).
  int splittingRefactorizations = 2;     ///< Splitting: new factorizations for a changed penalty.
  double rankTolerance = 1e-12;  ///< Relative eigenvalue below which A's Schur complement is treated as singular.
  /// Called with the share done (in [0, 1]) between the solver's steps (at least every ~0.1 s on a
  /// 2,000-node problem); returning false stops the solve with kc::Cancelled.
  Progress progress;
};

struct RigidityQpReport {
  bool converged = false;
  RigidityQpMethod method = RigidityQpMethod::ActiveSet;  ///< The method that produced the result.
  int iterations = 0;           ///< Active-set rounds (each a solve for the free pairs' multipliers) or ADMM iterations.
  int cgIterations = 0;         ///< Conjugate-gradient iterations (active set beyond maxDensePairs).
  Index workingRows = 0;       ///< Active set: constrained rows the dual was taken over (the rest never violated).
  int workingSets = 0;          ///< Active set: working sets solved (1 + the times violated rows joined).
  double primalResidual = 0.0;  ///< Splitting: max |Kc ΔU − S| (S the projected split variable).
  double dualResidual = 0.0;
  double violation = 0.0;       ///< max(0, L − Kc ΔU): how far the bounds are missed.
  double objective = 0.0;       ///< tr(ΔUᵀ H ΔU) + 2 tr(ΔUᵀ G) at the returned ΔU.
  double penalty = 0.0;
  double factorSeconds = 0.0, seconds = 0.0;
  bool factorFailed = false;    ///< Splitting: 2H + μ KcᵀKc could not be factorized (ΔU = 0 returned).
};

/// tr(ΔUᵀ H ΔU) + 2 tr(ΔUᵀ G) for ΔU n×m.
double rigidityObjective(const RigidityQp& qp, const RowMatrix& dU);

/// Solves the QP above; returns ΔU (n×m). Throws std::invalid_argument for inconsistent shapes.
/// Active set: from the equality-constrained optimum Y0, the multipliers Λ ≥ 0 (c×m') of the bounds
/// minimize ½⟨Λ, Kq Λ P⟩ − ⟨L − Kc Y0 Zᵀ, Λ⟩ (Kq = Kc (2H)⁻¹_A Kcᵀ, P = ZZᵀ on the active controls),
/// by proximal point steps Λ_{k+1} = argmin_{Λ≥0} d(Λ) + ε/2‖Λ − Λ_k‖², each a linear
/// complementarity problem with the positive definite Q + εI solved by block principal pivoting
/// (Júdice & Pires 1994: the primal-dual active set exchange, Murty's single pivot when the count of
/// infeasible pairs stops falling); Y = Y0 + (2H)⁻¹_A Kcᵀ Λ Z'. Each ADMM iteration (Splitting):
/// Y ← argmin tr(YᵀHY) + 2tr(YᵀGZ) + μ/2‖Kc Y − (S − Λ)Z'‖² s.t. A Y = 0 (the factorization plus A's
/// a×a Schur complement), V = α Kc Y Z'ᵀ + (1 − α) S, S ← Π(V + Λ), Λ ← Λ + V − S, where Π projects
/// each row onto its polytope {d ≥ L_i, d [1 C'] = 0} over the active controls (detail::RowPolytope;
/// there are no upper bounds), the iteration accelerated by Anderson's method.
RowMatrix solveRigidityQp(const RigidityQp& qp, const RigidityQpOptions& options = {}, RigidityQpReport* report = nullptr);

}  // namespace kc
