// LBC backend: solve time, ADMM iterations, optimality and peak memory on the bundled star
// (10 controls) and figure (30 controls) at about 2k / 5k / 20k mesh vertices, 2 threads; and
// the locality of LBC and of default kernel coordinates on the bundled star and figure.
//
// Optimality is certified, not estimated: LbcOptions::certify turns the final ADMM multipliers
// into a dual-feasible point whose value is a lower bound on the optimum (weak duality), so
// "gap_pct" = (objective − lower bound)/lower bound bounds how far the returned weights are from
// the optimal objective. The default solve stops on that certificate (gap ≤ 0.1%), so its checks
// ("certify_s") are part of the measured time.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>

#include "kc/app/diagnostics.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/lbc_solver.h"
#include "kc/core/parallel.h"

namespace {

using namespace kc;

const char* kExamples[] = {"star", "figure"};

Cage exampleCage(int example) { return app::loadCage(std::string(KC_SOURCE_DIR) + "/images/" + kExamples[example] + ".cage.json"); }

/// A line of /proc/self/status in kB ("VmRSS", "VmHWM").
double statusKb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1));
  return 0.0;
}

/// CPU seconds of the whole process (all threads): with a shared, loaded machine the wall time
/// depends on the load, this much less.
double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Threads of the solve benchmarks: 2 (the speed goals are for 2 cores), or KC_BENCH_THREADS.
int benchThreads() {
  const char* env = std::getenv("KC_BENCH_THREADS");
  return env ? std::max(1, std::atoi(env)) : 2;
}

/// Resets the peak resident set size (VmHWM) to the current one (Linux clear_refs 5).
void resetPeak() { std::ofstream("/proc/self/clear_refs") << "5"; }

/// args: example (0 star, 1 figure), target vertex count.
void BM_LbcSolve(benchmark::State& state) {
  const ScopedThreadCount threads(benchThreads());
  const Cage cage = exampleCage(int(state.range(0)));
  CageMeshOptions mo;
  mo.spacing = spacingForVertexCount(cage, state.range(1));
  const CageMesh mesh = meshCageInterior(cage, mo);
  LbcOptions options;
  options.certify = true;
  LbcReport report;
  double peakKb = 0.0, cpuSeconds = 0.0;
  for (auto _ : state) {
    resetPeak();
    const double baseKb = statusKb("VmRSS");
    const double cpu0 = processCpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    const LbcSolver solver(mesh, options.tau);
    const LbcResult r = solver.solve(options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.SetIterationTime(seconds);
    cpuSeconds = processCpuSeconds() - cpu0;
    peakKb = statusKb("VmHWM") - baseKb;
    report = r.report;
    benchmark::DoNotOptimize(r.W.data());
  }
  state.counters["vertices"] = double(mesh.size());
  state.counters["controls"] = double(mesh.controls);
  state.counters["iterations"] = report.iterations;
  state.counters["converged"] = report.status == SolveStatus::Ok;
  state.counters["objective"] = report.objective;
  state.counters["gap_pct"] = 100.0 * (report.objective - report.lowerBound) / report.lowerBound;
  state.counters["primal"] = report.primalResidual;
  state.counters["dual"] = report.dualResidual;
  state.counters["peak_kB_per_vertex"] = peakKb / double(mesh.size());
  state.counters["certify_s"] = report.certifySeconds;
  state.counters["iterate_s"] = report.iterationSeconds - report.certifySeconds;
  state.counters["setup_s"] = report.geodesicSeconds + report.factorSeconds;
  state.counters["process_cpu_s"] = cpuSeconds;
}
BENCHMARK(BM_LbcSolve)
    ->ArgNames({"figure", "vertices"})
    ->ArgsProduct({{0, 1}, {2000, 5000, 20000}})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

/// Locality inside the cage (LBC paper eq. 19–21, as `kcwarp-cli stats`) of the default binds.
/// args: example (0 star, 1 figure), backend (0 kc, 1 lbc).
void BM_Locality(benchmark::State& state) {
  const ScopedThreadCount threads(2);
  const Cage cage = exampleCage(int(state.range(0)));
  const auto [w, h] = state.range(0) == 0 ? std::pair(320, 320) : std::pair(320, 400);
  app::BindParams p = app::frameBindParams();
  p.backend = state.range(1) == 0 ? "kc" : "lbc";
  app::Diagnostics d;
  for (auto _ : state) {
    const app::Session s = app::bind(cage, w, h, p);
    d = app::diagnose(s);
  }
  state.counters["mean_influencing"] = d.locality.meanInfluencing;
  for (std::size_t i = 0; i < d.locality.t.size(); ++i)
    if (d.locality.t[i] == 1e-3) state.counters["P(1e-3)"] = d.locality.P[i];
  for (std::size_t k = 2; k < d.locality.Q.size() && k <= 6; k += 2) state.counters["Q(" + std::to_string(k) + ")"] = d.locality.Q[k];
  state.counters["inside_pu"] = d.inside.partitionOfUnity;
}
BENCHMARK(BM_Locality)->ArgNames({"figure", "lbc"})->ArgsProduct({{0, 1}, {0, 1}})->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
