#include "kc/app/pipeline.h"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace kc::app {
namespace {

void checkCommonParams(int width, int height, const BindParams& p) {
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide)
    throw std::invalid_argument("image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1.." + std::to_string(kMaxImageSide) + " pixels per side");
  if (!(p.spacing > 0.0) || !std::isfinite(p.spacing)) throw std::invalid_argument("spacing must be a positive number of pixels");
}

}  // namespace

double automaticSigma(double spacing) { return 3.0 * spacing / std::numbers::pi; }

Session bind(const Cage& cage, int width, int height, const BindParams& params, BindReport* report,
             const BindProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  validateCage(cage);
  checkCommonParams(width, height, params);
  const Backend& backend = backendFor(params.backend);
  BindReport local;
  BindReport& r = report ? *report : local;

  Session s;
  s.cage = cage;
  s.params = params;
  s.imageWidth = width;
  s.imageHeight = height;
  backend.bind(s, r, [&](const char* stage, double f) {
    if (progress && !progress(stage, f)) throw BindCancelled();
  });
  if (progress && !progress("done", 1.0)) throw BindCancelled();
  r.totalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  s.timings = {r.sampling.seconds, r.factor.assembleSeconds, r.factor.factorSeconds, r.init.seconds,
               r.optimize.seconds,  r.solveSeconds,           r.totalSeconds};
  return s;
}

OptimizeReport reoptimize(Session& session, Method method, std::span<const Index> subset,
                          std::vector<Index>* changedColumns) {
  const BackendCapabilities caps = sessionCapabilities(session);
  if (!caps.methods) throw std::invalid_argument("this session cannot be re-optimized: " + caps.why);
  return backendFor(session.params.backend).reoptimize(session, method, subset, changedColumns);
}

void refreshField(Session& session) { backendFor(session.params.backend).rebuildField(session); }

}  // namespace kc::app
