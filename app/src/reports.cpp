// Solver outcomes in words (bind's summary, stats, the session's reports block, the GUI).

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "kc/app/session.h"
#include "kc/app/text.h"

namespace kc::app {
namespace {

}  // namespace

std::vector<std::string> SolverReports::problems() const {
  std::vector<std::string> out;
  if (lbcMesh > 0) {
    if (lbc.status != SolveStatus::Ok)
      out.push_back(format("LBC: not converged after %d iterations (primal %.2e, dual %.2e)", lbc.iterations,
                           lbc.primalResidual, lbc.dualResidual));
    if (lbc.projectionFailures > 0)
      out.push_back(format("LBC: %ld vertices not projected to w >= 0 with certainty", static_cast<long>(lbc.projectionFailures)));
  }
  if (!sampling.converged)
    out.push_back(format("sampling: the blue-noise relaxation did not converge (largest move %.3g h after %d iterations)",
                         sampling.lastMove, sampling.iterations));
  if (init.fallbackSamples > 0)
    out.push_back(format("targets: %ld samples unreachable by heat diffusion (inverse-distance targets used)",
                         static_cast<long>(init.fallbackSamples)));
  if (init.unscreenedSamples > 0)
    out.push_back(format("targets: %ld samples screened to nothing (unscreened targets used)",
                         static_cast<long>(init.unscreenedSamples)));
  if (optimize.failed > 0)
    out.push_back(format("optimization: %ld samples not solved to optimality (fallback weights used)",
                         static_cast<long>(optimize.failed)));
  return out;
}

bool SolverReports::anyProblem() const { return !problems().empty(); }

std::string SolverReports::summary() const {
  std::string s = lbcMesh > 0
                      ? format("solver: LBC on %ld vertices, %d ADMM iterations, residuals primal %.2e dual %.2e, objective %.6g "
                               "(certified within %.3g%% of the optimum), %ld vertices projected to w >= 0",
                               static_cast<long>(lbcMesh), lbc.iterations, lbc.primalResidual, lbc.dualResidual, lbc.objective,
                               100.0 * (lbc.objective - lbc.lowerBound) / std::abs(lbc.lowerBound),
                               static_cast<long>(lbc.projectedVertices))
                      : format("solver: %ld samples optimized, %ld outside the control hull (hull fallback)",
                         static_cast<long>(optimize.solved), static_cast<long>(optimize.infeasible));
  const std::vector<std::string> p = problems();
  if (p.empty()) return s + "; no failures";
  s += "; WARNING: ";
  for (std::size_t k = 0; k < p.size(); ++k) s += (k ? "; " : "") + p[k];
  return s;
}

}  // namespace kc::app
