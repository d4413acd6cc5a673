#pragma once
/// The joint sparse QP of a rigid region (docs/rigidity.md; thesis 5.35 rewritten for the exact
/// interpolation): the change ΔU of the kernel coefficients of the nodes near the region,
///   min_ΔU  tr(ΔUᵀ H ΔU) + 2 tr(ΔUᵀ G)
///   s.t.    ΔU = Y Zᵀ            (every row of ΔU in span Z: partition of unity and reproduction)
///           A ΔU = 0             (polynomial side condition PᵀΔU = 0, held samples unchanged)
///           L ≤ Kc ΔU ≤ Up       (non-negativity of the constrained samples' weights)
/// solved by a primal-dual active set on the lower bounds (one CHOLMOD factorization of 2H, the
/// columns F = (2H)⁻¹_A Kcᵀ of the active rows, a dense system over the active pairs), or by ADMM
/// (Boyd et al. 2011, §3; OSQP's splitting) on one factorization of 2H + μ KcᵀKc shared by all
/// columns of Y — when upper bounds are given or the active set does not settle.

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
  RowMatrix Up;     ///< c×m upper bounds, ≥ 0 (+∞ allowed); empty: all +∞.
};

/// How the QP is solved: a primal-dual active set on the bounds (one factorization of 2H; falls
/// back to ADMM when it does not settle), or ADMM throughout.
enum class RigidityQpMethod { ActiveSet, Admm };

struct RigidityQpOptions {
  RigidityQpMethod method = RigidityQpMethod::ActiveSet;
  int maxActiveSetRounds = 50;   ///< Active-set rounds before falling back to ADMM.
  Index maxActivePairs = 4000;   ///< Active (sample, control) pairs beyond which it falls back to ADMM (a dense system of this size).
  double activeSetPenalty = 1e8; ///< ρ of the augmented Lagrangian on the bounds, relative to the largest diagonal entry of Q.
  double penalty = 0.0;        ///< ADMM penalty μ; ≤ 0: trace(2H) / trace(KcᵀKc).
  double relaxation = 1.6;     ///< Over-relaxation α ∈ (0, 2).
  double tolerance = 1e-8;     ///< Stop when the largest constraint violation (weights) ≤ tolerance and the
  double dualTolerance = 1e-6; ///< dual residual ≤ dualTolerance · max|2 G Z|.
  int maxIterations = 20000;
  double rankTolerance = 1e-12;  ///< Relative eigenvalue below which A's Schur complement is treated as singular.
};

struct RigidityQpReport {
  bool converged = false;
  RigidityQpMethod method = RigidityQpMethod::ActiveSet;  ///< The method that produced the result.
  int iterations = 0;           ///< Active-set rounds or ADMM iterations.
  double primalResidual = 0.0;  ///< max |Kc ΔU − S| (S the projected split variable).
  double dualResidual = 0.0;
  double violation = 0.0;       ///< max(0, L − Kc ΔU, Kc ΔU − Up): how far the bounds are missed.
  double objective = 0.0;       ///< tr(ΔUᵀ H ΔU) + 2 tr(ΔUᵀ G) at the returned ΔU.
  double penalty = 0.0;
  double factorSeconds = 0.0, seconds = 0.0;
  bool factorFailed = false;    ///< 2H + μ KcᵀKc could not be factorized (ΔU = 0 returned).
};

/// tr(ΔUᵀ H ΔU) + 2 tr(ΔUᵀ G) for ΔU n×m.
double rigidityObjective(const RigidityQp& qp, const RowMatrix& dU);

/// Solves the QP above; returns ΔU (n×m). Throws std::invalid_argument for inconsistent shapes.
/// Active set (Hintermüller, Ito & Kunisch 2002): from the equality-constrained optimum Y0, rounds
/// of: hold the active (row i, control c) pairs at their bounds, Σ_b (k_iᵀF_j)(z_c·z_d) λ_b =
/// L_a − (Kc Y0 Zᵀ)_a, Y = Y0 + Σ_b λ_b F_j z_dᵀ; keep the pairs with λ > 0, add the violated ones;
/// stop when the set repeats (then the KKT conditions hold). Each ADMM iteration: Y ← argmin tr(YᵀHY) + 2tr(YᵀGZ) + μ/2‖Kc Y − (S − Λ)Z‖² s.t. A Y = 0
/// (the factorization plus A's a×a Schur complement), V = α Kc Y Zᵀ + (1 − α) S,
/// S ← clamp(V + Λ, L, Up), Λ ← Λ + V − S.
RowMatrix solveRigidityQp(const RigidityQp& qp, const RigidityQpOptions& options = {}, RigidityQpReport* report = nullptr);

}  // namespace kc
