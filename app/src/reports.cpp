// Solver outcomes in words (bind's summary, stats, the session's reports block, the GUI).

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "kc/app/session.h"
#include "kc/app/text.h"

namespace kc::app {

std::vector<std::string> BindReport::problems() const {
  std::vector<std::string> out = backend ? backend->problems() : std::vector<std::string>{};
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

bool BindReport::anyProblem() const { return !problems().empty(); }

std::string BindReport::summary() const {
  std::string s = "solver: " + (backend ? backend->summary()
                                        : format("%ld samples optimized, %ld outside the control hull (hull fallback)",
                                                 static_cast<long>(optimize.solved), static_cast<long>(optimize.infeasible)));
  const std::vector<std::string> p = problems();
  if (p.empty()) return s + "; no failures";
  s += "; WARNING: ";
  for (std::size_t k = 0; k < p.size(); ++k) s += (k ? "; " : "") + p[k];
  return s;
}

}  // namespace kc::app
