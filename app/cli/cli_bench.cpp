// kcwarp-cli bench: performance tables of the bind pipeline and of the per-sample optimizers,
// measured on real bound cages (not timed tests: run it and read the table).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "cli_common.h"
#include "kc/app/export.h"
#include "kc/app/pipeline.h"
#include "kc/core/parallel.h"

namespace kc::cli {
namespace {

/// A non-convex blob of m control points, centred in a size×size image.
Cage blobCage(int m, double size) {
  Points C(m, 2);
  for (int i = 0; i < m; ++i) {
    const double t = 2.0 * std::numbers::pi * i / m;
    const double r = 0.36 * size * (1.0 + 0.18 * std::sin(5.0 * t));
    C.row(i) << 0.5 * size + r * std::cos(t), 0.5 * size - r * std::sin(t);
  }
  return Cage::polygon(C);
}

}  // namespace

void benchLines(const std::string& cagePath, int sets, int repeats, bool crossing);  // cli_bench_lines.cpp
void benchEdges(const std::string& folder, int repeats);                // cli_bench_lines.cpp
void benchRigid(const std::string& imagesDir, int repeats, const std::string& speedOnly);  // cli_bench_rigid.cpp
void benchGraded(const std::string& folder, int repeats);                                 // cli_bench_graded.cpp
void benchBackends(const std::vector<std::string>& cages, int repeats);                   // cli_bench_graded.cpp

namespace {

struct BenchArgs {
  int samples = 10000;
  int repeats = 3;
  int threads = 0;
  bool lines = false, edges = false;
  bool rigid = false, graded = false;
  std::vector<std::string> backends;
  std::string narrow = "tests/data/narrow";
  std::string rigidSpeed;
  std::string images = "images";
  int lineSets = 10;
  bool crossing = false;
  std::string cage = "images/star.cage.json";
};

void benchBind(const BenchArgs& a) {
  const int m = 34;
  const double size = 512.0;
  // Samples cover the image plus an automatic margin of ~3h per side: ((size + 6h) / h)² ≈ N.
  app::BindParams p = app::frameBindParams();
  p.spacing = size / (std::sqrt(static_cast<double>(a.samples)) - 6.0);
  std::vector<double> t[8];
  Index n = 0;
  for (int r = 0; r < a.repeats; ++r) {
    const app::Session s = app::bind(blobCage(m, size), static_cast<int>(size), static_cast<int>(size), p);
    n = s.samples.size();
    const app::BindTimings& b = s.report.timings;
    const double v[8] = {b.sampling, b.assemble, b.factor, b.init, b.optimize, b.solve, b.total, 0};
    for (int k = 0; k < 7; ++k) t[k].push_back(v[k]);
  }
  std::printf("bind: %ld samples, m = %d, spacing %.2f px, %d threads, median of %d runs\n", static_cast<long>(n), m, p.spacing,
              threadCount(), a.repeats);
  const char* names[7] = {"sampling", "kernel assembly", "factorization", "initial weights (heat)", "optimization (QP)",
                          "U = K^-1 W", "total"};
  for (int k = 0; k < 7; ++k) std::printf("  %-24s %9.1f ms\n", names[k], 1e3 * median(t[k]));
}

void benchOptimizers(const BenchArgs& a) {
  std::printf("\nper-sample optimization, 1 thread, real heat-diffusion targets (median of %d runs):\n", a.repeats);
  std::printf("  %4s %9s %12s %12s %12s %9s %9s\n", "m", "samples", "QEC ns", "QP ns", "L1 ns", "QP/QEC", "L1/QEC");
  for (int m : {4, 10, 34}) {
    app::BindParams p = app::frameBindParams();
    p.spacing = 4.0;
    const app::Session s = app::bind(blobCage(m, 400.0), 400, 400, p);
    std::vector<Index> rows;
    for (Index i = 0; i < s.samples.size(); ++i)
      if (s.samples.kind[static_cast<std::size_t>(i)] == SampleKind::Interior) rows.push_back(i);
    const WeightOptimizer optimizer(s.cage.C);
    const ScopedThreadCount one(1);
    double ns[3];
    const Method methods[3] = {Method::QEC, Method::QP, Method::L1};
    for (int k = 0; k < 3; ++k) {
      std::vector<double> runs;
      Weights W = s.W;
      OptimizeOptions o;
      o.method = methods[k];
      for (int r = 0; r < a.repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        optimizer.optimize(s.samples, s.W0, W, o, rows);
        runs.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count());
      }
      ns[k] = median(runs) / static_cast<double>(rows.size());
    }
    std::printf("  %4d %9zu %12.1f %12.1f %12.1f %8.1fx %8.1fx\n", m, rows.size(), ns[0], ns[1], ns[2], ns[1] / ns[0],
                ns[2] / ns[0]);
  }
}

/// A paint stroke's release as the GUI does it (ui/src/jobs.cpp): re-optimize the painted samples,
/// re-solve and re-evaluate at the display mesh only the controls whose weights changed, re-weight
/// the mesh. 1-megapixel image, 30 controls, ~10k samples, display mesh at 4 px; with the default
/// lobe bound (KcParams::lobeBound: the sampler projects the vertices below it again) or without.
void benchStroke(const BenchArgs& a, double lobeBound) {
  const int m = 30;
  const double size = 1000.0;
  app::BindParams p = app::frameBindParams();
  p.spacing = size / (std::sqrt(static_cast<double>(a.samples)) - 6.0);
  p.kc.lobeBound = lobeBound;
  app::Session s = app::bind(blobCage(m, size), static_cast<int>(size), static_cast<int>(size), p);
  app::FieldSampler sampler;
  Weights vertexWeights;
  WarpMesh mesh = app::buildWarpMesh(s, app::warpMeshOptionsFor(s), nullptr, &sampler, &vertexWeights);
  Index bounded = 0;  // vertices a weight of which is at its bound
  if (const LobeBound* b = s.field->lobeBound()) {
    const std::vector<double> l = b->bounds(mesh.restVertices());
    for (Index i = 0; i < vertexWeights.rows(); ++i)
      bounded += std::abs(vertexWeights.row(i).minCoeff() - l[static_cast<std::size_t>(i)]) < 1e-12 ? 1 : 0;
  }
  std::printf(
      "\npaint stroke release: %ld samples, m = %d, display mesh %ld vertices (median of %d strokes), lobe bound %g "
      "(%ld vertices at it)\n",
      static_cast<long>(s.samples.size()), m, static_cast<long>(mesh.restVertices().rows()), a.repeats, lobeBound,
      static_cast<long>(bounded));
  std::vector<double> opt, remesh, total;
  std::vector<Index> columnsChanged, painted;
  for (int r = 0; r < a.repeats; ++r) {
    // A 40 px brush dab on control 3's side of the blob, adding 0.3 with a smooth falloff.
    const Vec2 centre = 0.5 * (Vec2(s.cage.C.row(3)) + Vec2(size / 2, size / 2)) + Vec2(7.0 * r, 0);
    std::vector<Index> rows;
    for (Index i = s.cage.size(); i < s.samples.size(); ++i) {
      const double d = (Vec2(s.samples.X.row(i)) - centre).norm();
      if (d < 40.0 && s.samples.kind[static_cast<std::size_t>(i)] == SampleKind::Interior) {
        s.W0(i, 3) += 0.3 * (1.0 - d / 40.0);
        s.W0.row(i) /= s.W0.row(i).sum();
        rows.push_back(i);
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Index> columns;
    app::reoptimize(s, Method::QP, rows, &columns);
    const auto t1 = std::chrono::steady_clock::now();
    sampler.updateColumns(*s.field, columns, vertexWeights);
    mesh.setWeights(vertexWeights);
    const auto t2 = std::chrono::steady_clock::now();
    opt.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    remesh.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    total.push_back(std::chrono::duration<double, std::milli>(t2 - t0).count());
    columnsChanged.push_back(static_cast<Index>(columns.size()));
    painted.push_back(static_cast<Index>(rows.size()));
  }
  std::printf("  painted samples %ld, controls changed %ld of %d\n", static_cast<long>(painted[0]),
              static_cast<long>(columnsChanged[0]), m);
  std::printf("  re-optimize + re-solve changed columns %9.1f ms\n", median(opt));
  std::printf("  re-evaluate mesh vertices + re-weight  %9.1f ms\n", median(remesh));
  std::printf("  stroke release total                   %9.1f ms\n", median(total));
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto a = std::make_shared<BenchArgs>();
  CLI::App* sub = app.add_subcommand("bench", "Performance tables: bind stages, per-sample optimizers, paint stroke release");
  sub->add_option("--samples", a->samples, "Target sample count of the bind benchmark")->capture_default_str();
  sub->add_option("--repeats", a->repeats, "Runs per figure (the median is shown)")->capture_default_str();
  sub->add_option("--threads", a->threads, "Threads (0 = all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  sub->add_flag("--lines", a->lines, "Only the structure-lines table (straightness, parallelism, bind time)");
  sub->add_flag("--edges", a->edges,
                "Only the linear-edges table: the bundled examples (the folder of --cage) with and without --linear-edges");
  sub->add_flag("--rigid", a->rigid, "Only the rigid-regions table (thesis Fig 6.37 set-up on the star, brush-release times)");
  sub->add_option("--images", a->images, "--rigid: the folder of the bundled examples (star, figure)")->capture_default_str();
  sub->add_option("--rigid-speed", a->rigidSpeed, "--rigid: only the brush-release speed rows: star, figure or both");
  sub->add_option("--backends", a->backends,
                  "Only the backends table: these cages bound with defaults by kc and by lbc, bind times and their ratio")
      ->expected(1, -1);
  sub->add_flag("--graded", a->graded,
                "Only the graded-sampling table: cages with narrow places against their gaps widened (both backends), "
                "and a neck on a 12 MP picture");
  sub->add_option("--narrow", a->narrow, "--graded: the folder of the narrow test cages")->capture_default_str();
  sub->add_option("--line-sets", a->lineSets, "--lines: random sets of lines")->capture_default_str();
  sub->add_flag("--crossing", a->crossing, "--lines: sets of three lines that cross (an X and a third across one), graded binds");
  sub->add_option("--cage", a->cage, "--lines: the cage (default: the bundled star)")->capture_default_str();
  sub->callback([a] {
    if (a->samples < 100 || a->samples > 1000000) throw app::InputError("--samples", "must be within 100..1000000");
    if (a->repeats < 1 || a->repeats > 100) throw app::InputError("--repeats", "must be within 1..100");
    const ScopedThreadCount threads(a->threads);
    if (!a->rigidSpeed.empty() && a->rigidSpeed != "star" && a->rigidSpeed != "figure" && a->rigidSpeed != "both")
      throw app::InputError("--rigid-speed", "must be star, figure or both (got '" + a->rigidSpeed + "')");
    if (!a->backends.empty()) {
      benchBackends(a->backends, a->repeats);
      return;
    }
    if (a->graded) {
      benchGraded(a->narrow, a->repeats);
      return;
    }
    if (a->rigid) {
      benchRigid(a->images, a->repeats, a->rigidSpeed);
      return;
    }
    if (a->edges) {
      benchEdges(std::filesystem::path(a->cage).parent_path().string(), a->repeats);
      return;
    }
    if (a->lines) {
      if (a->lineSets < 1 || a->lineSets > 1000) throw app::InputError("--line-sets", "must be within 1..1000");
      benchLines(a->cage, a->lineSets, a->repeats, a->crossing);
      return;
    }
    benchBind(*a);
    benchOptimizers(*a);
    benchStroke(*a, app::BindParams{}.kc.lobeBound);
    benchStroke(*a, 0.0);
  });
}

}  // namespace kc::cli
