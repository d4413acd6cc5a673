#include "kc/app/pipeline.h"

#include "kc/sampling/sigma.h"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace kc::app {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void checkParams(int width, int height, const BindParams& p) {
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide)
    throw std::invalid_argument("image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1.." + std::to_string(kMaxImageSide) + " pixels per side");
  if (!(p.spacing > 0.0) || !std::isfinite(p.spacing)) throw std::invalid_argument("spacing must be a positive number of pixels");
  if (!std::isfinite(p.sigma) || p.sigma < 0.0) throw std::invalid_argument("sigma must be positive (or 0 for automatic)");
  if (p.backend != "kc") throw std::invalid_argument("backend '" + p.backend + "' is not available (only 'kc')");
  if (p.init.iterations < 0) throw std::invalid_argument("heat iterations must be ≥ 0 (0 = steady state)");
}

GaussianKernel kernelFor(double sigma, double spacing) { return GaussianKernel::forSpacing(sigma, spacing); }

}  // namespace

double automaticSigma(double spacing) { return 3.0 * spacing / std::numbers::pi; }

Session bind(const Cage& cage, int width, int height, const BindParams& params, BindReport* report,
             const BindProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  validateCage(cage);
  checkParams(width, height, params);
  auto step = [&](const char* stage, double f) {
    if (progress && !progress(stage, f)) throw BindCancelled();
  };
  BindReport local;
  BindReport& r = report ? *report : local;

  Session s;
  s.cage = cage;
  s.params = params;
  s.imageWidth = width;
  s.imageHeight = height;

  step("sampling", 0.0);
  sampling::SamplingOptions so;
  so.spacing = params.spacing;
  so.width = width;
  so.height = height;
  // The plain (thesis) interpolation is accurate only a few kernel widths inside the sampled
  // domain (thesis Fig 3.1), so it gets a wider automatic margin than the exact one.
  so.margin = params.margin >= 0.0 || params.interp == InterpMode::Exact ? params.margin : kThesisMarginSpacings * params.spacing;
  so.kind = params.sampler;
  so.seed = params.seed;
  s.samples = sampling::sample(cage, so, &r.sampling);

  step("kernel", 0.25);
  s.sigma = params.sigma > 0.0 ? params.sigma : sampling::suggestSigma(s.samples);
  r.factor = s.field.interpolator.compute(s.samples.X, kernelFor(s.sigma, params.spacing), params.interp);
  if (!s.field.interpolator.ok())
    throw std::invalid_argument("the kernel matrix cannot be factorized (sigma " + std::to_string(s.sigma) + ", spacing " +
                                std::to_string(params.spacing) + "): " + r.factor.advice);

  step("initial weights", 0.5);
  s.W0 = initialWeights(s.samples, cage, s.field.interpolator.K(), params.init, &r.init);

  step("optimization", 0.7);
  s.W.resize(s.W0.rows(), s.W0.cols());
  const WeightOptimizer optimizer(cage.C);
  OptimizeOptions oo;
  oo.method = params.method;
  r.optimize = optimizer.optimize(s.samples, s.W0, s.W, oo);

  step("interpolation", 0.9);
  const auto ts = std::chrono::steady_clock::now();
  s.field.coefficients = s.field.interpolator.solve(s.W);
  r.solveSeconds = secondsSince(ts);
  step("done", 1.0);
  r.totalSeconds = secondsSince(t0);
  s.timings = {r.sampling.seconds, r.factor.assembleSeconds, r.factor.factorSeconds, r.init.seconds,
               r.optimize.seconds,  r.solveSeconds,           r.totalSeconds};
  return s;
}

OptimizeReport reoptimize(Session& session, Method method, std::span<const Index> subset,
                          std::vector<Index>* changedColumns) {
  const WeightOptimizer optimizer(session.cage.C);
  const bool whole = subset.empty() || session.W.rows() != session.W0.rows() || session.W.cols() != session.W0.cols();
  if (session.W.rows() != session.W0.rows() || session.W.cols() != session.W0.cols()) session.W = session.W0;
  const Index m = session.W0.cols();
  RowMatrix before(static_cast<Index>(subset.size()), m);
  if (!whole)
    for (std::size_t k = 0; k < subset.size(); ++k) before.row(static_cast<Index>(k)) = session.W.row(subset[k]);
  OptimizeOptions oo;
  oo.method = method;
  const OptimizeReport r = optimizer.optimize(session.samples, session.W0, session.W, oo, whole ? std::span<const Index>{} : subset);
  session.params.method = method;

  std::vector<Index> columns;
  for (Index c = 0; c < m; ++c) {
    bool changed = whole;
    for (std::size_t k = 0; k < subset.size() && !changed; ++k)
      changed = session.W(subset[k], c) != before(static_cast<Index>(k), c);
    if (changed) columns.push_back(c);
  }
  CoordinateField& f = session.field;
  if (f.interpolator.ok()) {
    if (whole || f.coefficients.U.rows() != session.W.rows() || f.coefficients.U.cols() != m)
      f.coefficients = f.interpolator.solve(session.W);
    else
      f.interpolator.solveColumns(session.W, columns, f.coefficients);
  }
  if (changedColumns) *changedColumns = std::move(columns);
  return r;
}

InterpolatorReport refreshField(Session& session) {
  InterpolatorReport r =
      session.field.interpolator.compute(session.samples.X, kernelFor(session.sigma, session.params.spacing), session.params.interp);
  if (session.field.interpolator.ok()) session.field.coefficients = session.field.interpolator.solve(session.W);
  return r;
}

}  // namespace kc::app
