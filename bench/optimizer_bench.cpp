// Per-sample cost of the weight optimizers (thesis Table 4.1): QP (4.1), QEC (4.2–4.6) and ℓ1
// (4.8) for m = 4, 10, 34 controls on one core. Realistic problems: controls on a slightly
// irregular circle (pixels), samples inside the cage, targets like heat-diffusion weights
// (positive, decaying with distance, summing to roughly 1, not already feasible).
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <random>

#include "kc/core/parallel.h"
#include "kc/core/weights/optimizer.h"

namespace kc {
namespace {

constexpr Index kSamples = 4096;

struct Problems {
  Points C;
  ControlFrame frame;
  Points X;    ///< normalized sample positions
  Weights W0;  ///< kSamples × m
  Weights W;
};

const Problems& problems(int m) {
  static std::map<int, Problems> cache;
  auto it = cache.find(m);
  if (it != cache.end()) return it->second;
  Problems p;
  std::mt19937 rng(static_cast<unsigned>(m));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double R = 200.0;
  p.C.resize(m, 2);
  for (int i = 0; i < m; ++i) {
    const double a = 2.0 * M_PI * (i + 0.2 * u(rng)) / m;
    const double r = R * (0.9 + 0.1 * u(rng));
    p.C.row(i) = Vec2(400 + r * std::cos(a), 300 + r * std::sin(a)).transpose();
  }
  p.frame = ControlFrame(p.C);
  // Kernel width ~ 1.5 control spacings (heat spreads over a few neighbours).
  const double sigma = 1.5 * 2.0 * M_PI * R / m;
  p.X.resize(kSamples, 2);
  p.W0.resize(kSamples, m);
  p.W.resize(kSamples, m);
  for (Index j = 0; j < kSamples; ++j) {
    Vec2 x;
    do {
      x = Vec2(400 + R * (2 * u(rng) - 1), 300 + R * (2 * u(rng) - 1));
    } while (p.frame.hullExcess(p.frame.normalize(x)) > -1e-3);
    p.X.row(j) = p.frame.normalize(x).transpose();
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
      const double d2 = (x - Vec2(p.C.row(i))).squaredNorm();
      p.W0(j, i) = std::exp(-d2 / (2 * sigma * sigma)) * (1.0 + 0.1 * u(rng));
      sum += p.W0(j, i);
    }
    p.W0.row(j) *= (0.9 + 0.2 * u(rng)) / sum;
  }
  return cache.emplace(m, std::move(p)).first->second;
}

template <class Solve>
void runBatch(benchmark::State& state, Solve solve) {
  const int m = static_cast<int>(state.range(0));
  Problems& p = const_cast<Problems&>(problems(m));
  const auto ms = static_cast<std::size_t>(m);
  int iterations = 0;
  Index notOptimal = 0;
  for (auto _ : state) {
    for (Index j = 0; j < kSamples; ++j) {
      const SampleReport r = solve(p.frame, Vec2(p.X.row(j)), std::span<const double>(p.W0.row(j).data(), ms),
                                   std::span<double>(p.W.row(j).data(), ms));
      iterations += r.iterations;
      notOptimal += r.status != SolveStatus::Ok;
    }
    benchmark::DoNotOptimize(p.W.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kSamples);
  // Seconds per sample (printed with an SI prefix, e.g. 45.2n = 45.2 ns).
  state.counters["per_sample"] = benchmark::Counter(static_cast<double>(kSamples),
                                                    benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["iter/sample"] = static_cast<double>(iterations) / static_cast<double>(state.iterations() * kSamples);
  state.counters["notOptimal"] = static_cast<double>(notOptimal);
}

void BM_Qec(benchmark::State& state) {
  runBatch(state, [](const ControlFrame& f, const Vec2& x, std::span<const double> w0, std::span<double> w) {
    sampleQec(f, x, w0, w);
    return SampleReport{};
  });
}
void BM_Qp(benchmark::State& state) {
  runBatch(state, [](const ControlFrame& f, const Vec2& x, std::span<const double> w0, std::span<double> w) {
    return sampleQp(f, x, w0, w);
  });
}
void BM_L1(benchmark::State& state) {
  runBatch(state, [](const ControlFrame& f, const Vec2& x, std::span<const double> w0, std::span<double> w) {
    return sampleL1(f, x, w0, w);
  });
}

BENCHMARK(BM_Qec)->Arg(4)->Arg(10)->Arg(34);
BENCHMARK(BM_Qp)->Arg(4)->Arg(10)->Arg(34);
BENCHMARK(BM_L1)->Arg(4)->Arg(10)->Arg(34);

}  // namespace
}  // namespace kc

BENCHMARK_MAIN();
