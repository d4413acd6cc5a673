#pragma once
/// Local barycentric coordinates (Zhang et al. 2014, "LBC"): per-vertex weights on a mesh of the
/// cage interior minimizing the weighted total variation (paper eq. 10, 14)
///   Σ_s Σ_i φ_i^s a_s |∇_s w_i|   s.t.  W K = B (reproduction, partition of unity), W ≥ 0,
///   Lagrange at the controls and linear along cage edges (Dirichlet data, eq. 5),
/// solved by ADMM in the null-space form W = Y M + H (eq. 15–17, Appendix B).

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <string_view>

#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/names.h"
#include "kc/core/lbc/mesh_operators.h"
#include "kc/core/solve.h"

namespace kc {

/// τ in φ_i = τ(D_i) (paper eq. 11): D_i the geodesic distance to control i normalized by its maximum.
enum class LbcTau { Square, Constant, Linear, Sqrt };

template <>
struct EnumNames<LbcTau> {
  static constexpr std::array<std::pair<LbcTau, std::string_view>, 4> table{
      {{LbcTau::Square, "square"}, {LbcTau::Constant, "const"}, {LbcTau::Linear, "linear"}, {LbcTau::Sqrt, "sqrt"}}};
};

/// τ(x) for x ∈ [0, 1]: x², 1, x, √x.
double lbcTau(LbcTau tau, double x);

struct LbcOptions {
  LbcTau tau = LbcTau::Square;  ///< τ of φ (eq. 13); LbcSolver takes it at construction.
  /// Stopping rule: the primal and the dual residual (eq. 26–27), each as an area-weighted RMS
  /// per control function on the mesh scaled to bounding-box diameter 1, are ≤ tolerance. These
  /// are discretizations of L² norms of functions, so the rule does not loosen as the mesh is refined.
  /// (The residuals, not the gap alone, keep the weights' small tails converged: a weight's
  /// support, what the locality measures count, settles later than the objective.)
  double tolerance = 1e-3;
  int maxIterations = 20000;
  /// μ at the start (normalized units: bounding-box diameter 1); a fixed 0.03 takes fewer
  /// iterations to the certified gap than larger μ or residual balancing.
  double penalty = 0.03;
  bool adaptivePenalty = false;     ///< Residual balancing (Boyd et al. 2011 §3.4.1): μ ×/÷ 2 when one residual is 10× the other.
  /// α, over-relaxation (Appendix B suggests [1.5, 1.8]; 1.9 took the fewest iterations to the
  /// certified stop on the bundled figure).
  double relaxation = 1.9;
  bool harmonicStart = true;        ///< Warm start from harmonic coordinates (else Y = 0).
  bool projectNonNegative = true;   ///< Final per-vertex QP (thesis 4.1) onto w ≥ 0 keeping W K = B.
  /// Certified stopping: once the residuals are below `tolerance`, the solver stops at the first
  /// check where (objective − lower bound) ≤ gapTolerance·lower bound, the lower bound from the
  /// ADMM multipliers (a duality-gap certificate, LbcReport::lowerBound). Checked on a geometric
  /// schedule, each check with the last iterate and with averages (Z's over the iterations since
  /// the previous check, U1's over all, iteration t weighted by t²), whichever gives the lower
  /// objective and the higher bound (each check: up to two projections, their objectives and two
  /// small LPs per vertex). 0 = residuals only.
  double gapTolerance = 1e-3;
  /// Compute LbcReport::lowerBound at the end even when gapTolerance is 0.
  bool certify = false;
  /// Called every 10 iterations with the residuals' way down to `tolerance` (log scale; the dual
  /// residual as last computed, which is where the stop reads it; with a gap to certify, 90% of
  /// the bar, the last 10% the gap's way from the first check down to gapTolerance) or the share
  /// of maxIterations done, whichever is further, never decreasing; returning false throws
  /// kc::Cancelled. Called on the calling thread.
  Progress progress;
};

struct LbcReport {
  /// Ok (residuals ≤ tolerance and the gap certified), NotConverged (maxIterations first: the
  /// weights are the last iterate, its average or, if lower in objective, one checked before,
  /// still exact barycentric) or Singular (a factorization failed, the mesh is degenerate: no weights).
  SolveStatus status = SolveStatus::Ok;
  int iterations = 0;
  double primalResidual = 0.0, dualResidual = 0.0;  ///< At the last iteration (see LbcOptions::tolerance).
  double penalty = 0.0;                             ///< μ at the end.
  double objective = 0.0;    ///< Σ φ a |∇w| of the returned weights (normalized units: diameter 1).
  Index projectedVertices = 0;  ///< Vertices whose weights the final QP changed (negative entries).
  double maxProjection = 0.0;   ///< max |w − w_affine| over those vertices.
  Index projectionFailures = 0; ///< Vertices where the QP did not certify its optimum.
  /// With LbcOptions::gapTolerance > 0 or certify: a lower bound on the optimum of (15) (weak
  /// duality), so the returned weights are within (objective − lowerBound)/lowerBound of optimal.
  /// −∞ otherwise.
  double lowerBound = -std::numeric_limits<double>::infinity();
  double geodesicSeconds = 0.0, factorSeconds = 0.0, iterationSeconds = 0.0, seconds = 0.0;
  double certifySeconds = 0.0;  ///< Part of `seconds` spent on lower bounds (and their projections).
};

struct LbcResult {
  Weights W;  ///< #V×m per-vertex weights of the mesh (rows 0..nb−1 the Dirichlet data).
  LbcReport report;
};

/// Precomputation for one mesh and one τ: normalized geometry, geodesic weights φ (heat method),
/// the null-space basis M and H (eq. 15–17), the Dirichlet data, and the factorization of the
/// Y-system. solve() runs ADMM; it can be called several times (e.g. with different tolerances).
class LbcSolver {
 public:
  /// mesh: from meshCageInterior (status Ok). Throws std::invalid_argument for an empty mesh or
  /// fewer than 3 controls. A failed factorization is reported by solve() (status Singular).
  LbcSolver(const CageMesh& mesh, LbcTau tau);
  ~LbcSolver();
  LbcSolver(const LbcSolver&) = delete;
  LbcSolver& operator=(const LbcSolver&) = delete;

  /// ADMM (Appendix B) with the area-weighted inner products described in lbc_solver.cpp;
  /// returns #V×m weights. Bit-identical for any thread count. options.tau must be the τ the
  /// solver was built with (φ is precomputed for it): std::invalid_argument otherwise.
  LbcResult solve(const LbcOptions& options = {}) const;

  /// The discrete objective Σ_s Σ_i φ_i^s a_s |∇_s w_i| (eq. 14) of #V×m weights W (normalized units).
  double objective(const Weights& W) const;
  /// The Dirichlet data of the boundary vertices (nb×m): Lagrange at controls, linear on edges (eq. 5).
  const Weights& boundaryWeights() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

/// One-shot: LbcSolver(mesh, options.tau).solve(options).
LbcResult solveLbc(const CageMesh& mesh, const LbcOptions& options = {});

}  // namespace kc
