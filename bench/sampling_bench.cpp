// Blue-noise sampling cost: per-iteration inverse mean shift (should grow linearly with the
// number of samples) and full relaxation to convergence, at 2.5k, 10k and 40k samples.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "kc/sampling/blue_noise.h"
#include "kc/sampling/sampler.h"

namespace {

using namespace kc;
using namespace kc::sampling;

constexpr double kH = 6.0;

/// Image whose sampled domain (plus the 3h margin) holds about n samples at spacing kH, with a
/// five-pointed star cage in its middle.
struct Scene {
  Cage cage;
  SamplingOptions options;
};

Scene scene(Index n) {
  Scene s;
  const double side = kH * std::sqrt(static_cast<double>(n)) - 6.0 * kH;
  s.options.spacing = kH;
  s.options.width = side;
  s.options.height = side;
  s.options.kind = SamplerKind::BlueNoise;
  Points C(10, 2);
  for (int i = 0; i < 10; ++i) {
    const double a = -std::numbers::pi / 2 + std::numbers::pi * i / 5.0, r = (i % 2 == 0 ? 0.4 : 0.17) * side;
    C.row(i) << 0.5 * side + r * std::cos(a), 0.5 * side + r * std::sin(a);
  }
  s.cage = Cage::polygon(C);
  return s;
}

/// Cost of one inverse mean shift iteration (fixed iteration count, no early stop).
void BM_InverseMeanShiftIteration(benchmark::State& state) {
  const Scene s = scene(state.range(0));
  const Rect domain = samplingDomain(s.options);
  BlueNoiseOptions bo;
  bo.relax.maxIterations = 0;  // only the fixed samples and the random start
  const BlueNoiseResult start = blueNoiseSample(s.cage, domain, kH, 1, bo);
  const Index firstFree = start.samples.size() - start.interiorCount - start.exteriorCount;
  InverseMeanShiftOptions o;
  o.spacing = kH;
  o.maxIterations = 10;
  o.tolerance = 0.0;
  RelaxRegion region;
  region.cage = &s.cage;
  region.domain = domain;
  for (auto _ : state) {
    Points X = start.samples.X;
    relaxInverseMeanShift(X, firstFree, region, o);
    benchmark::DoNotOptimize(X.data());
  }
  state.counters["samples"] = static_cast<double>(start.samples.size());
  state.counters["ns_per_sample_iter"] = benchmark::Counter(
      static_cast<double>(start.samples.size() - firstFree) * o.maxIterations, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_InverseMeanShiftIteration)->Arg(2500)->Arg(10000)->Arg(40000)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Whole blue-noise sampling, relaxed to convergence.
void BM_BlueNoiseSample(benchmark::State& state) {
  const Scene s = scene(state.range(0));
  SamplingReport report;
  Index n = 0;
  for (auto _ : state) {
    const SampleSet S = sample(s.cage, s.options, &report);
    n = S.size();
    benchmark::DoNotOptimize(S.X.data());
  }
  state.counters["samples"] = static_cast<double>(n);
  state.counters["iterations"] = report.iterations;
  state.counters["converged"] = report.converged ? 1 : 0;
}
BENCHMARK(BM_BlueNoiseSample)->Arg(2500)->Arg(10000)->Arg(40000)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Grid sampling, for comparison.
void BM_GridSample(benchmark::State& state) {
  Scene s = scene(state.range(0));
  s.options.kind = SamplerKind::Grid;
  for (auto _ : state) benchmark::DoNotOptimize(sample(s.cage, s.options).X.data());
}
BENCHMARK(BM_GridSample)->Arg(2500)->Arg(10000)->Arg(40000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
