#pragma once
/// The one vocabulary of kcwarp's numerical solves: their outcome (SolveStatus), how they report
/// progress (Progress, StageProgress) and how they are stopped (Cancelled).

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>

namespace kc {

/// The outcome of a solve in core: a factorization, a per-sample QP or L1 problem, a mesh, the LBC
/// iteration. Each solver's report documents which of these it returns and what it hands back then.
enum class SolveStatus {
  Ok,            ///< Solved: factored, converged or certified to the solver's tolerance.
  NotComputed,   ///< Nothing solved yet.
  NotConverged,  ///< The iteration limit came first; the solver's documented fallback is returned.
  Infeasible,    ///< The constraints cannot all hold (a QP sample outside the controls' hull); fallback returned.
  Singular,      ///< A matrix could not be factored (singular, or not positive definite where it must be).
  TooLarge,      ///< The problem exceeds a size cap of its options (a mesh's vertex cap); nothing returned.
  OutOfMemory,   ///< An allocation failed; nothing returned.
};

/// How far a long computation is, `fraction` in [0, 1], never decreasing. Returning false asks it
/// to stop: it throws Cancelled at its next check. Called on the computation's thread.
using Progress = std::function<bool(double fraction)>;

/// The share done of an iteration that stops once a quantity, falling roughly geometrically from
/// `start`, reaches `target`: log(start / value) / log(start / target) in [0, 1]; 1 once value ≤
/// target, 0 while start ≤ target < value. (The sampler's relaxation and the LBC iteration report
/// it, at least their iteration share, never decreasing.)
inline double logProgress(double value, double start, double target) {
  if (!(value > target)) return 1.0;
  if (!(start > target)) return 0.0;
  return std::clamp(std::log(start / value) / std::log(start / target), 0.0, 1.0);
}

/// Progress of a computation of named stages (a bind, a rigidity stroke): `stage` names the stage
/// running, `fraction` the whole computation's share done.
using StageProgress = std::function<bool(const char* stage, double fraction)>;

/// Thrown when a progress callback asks a long computation to stop (a bind, the LBC iteration,
/// sampling, the rigidity QP; app::setRigidity first puts the session back as it was). Whoever
/// asked catches it; nothing else does.
class Cancelled : public std::exception {
 public:
  const char* what() const noexcept override { return "cancelled"; }
};

}  // namespace kc
