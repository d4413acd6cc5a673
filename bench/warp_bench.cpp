// Warp speed goals: re-deforming the warp mesh of a 1-megapixel image for a new pose
// (goal ≤ 2 ms) and full-resolution export of a 2048×2048 image (goal ~100 ms on 2 cores).
// Weights: mean value coordinates of a 24-point star-shaped cage — dense, i.e. every vertex keeps
// all 24 entries, a pessimistic stand-in for kernel coordinates (which keep 4–25 in the demo).

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <numbers>

#include "kc/core/parallel.h"
#include "kc/core/warp_mesh.h"

namespace {

using namespace kc;

/// Mean value coordinates of the closed polygon C at X (#X×m); points on edges/vertices get
/// linear/Lagrange weights.
Weights meanValue(const Points& C, const Points& X) {
  const Index m = C.rows();
  Weights W = Weights::Zero(X.rows(), m);
  parallelFor(X.rows(), [&](Index p) {
    const Points S = C.rowwise() - X.row(p);
    const Eigen::VectorXd r = S.rowwise().norm();
    Eigen::VectorXd t = Eigen::VectorXd::Zero(m);
    for (Index i = 0; i < m; ++i) {
      if (r(i) < 1e-9) {
        W.row(p).setZero();
        W(p, i) = 1;
        return;
      }
      const Index j = (i + 1) % m;
      const double A = 0.5 * (S(i, 0) * S(j, 1) - S(i, 1) * S(j, 0)), D = S.row(i).dot(S.row(j));
      if (std::abs(A) < 1e-12 * r(i) * r(j)) {
        if (D < 0) {
          W.row(p).setZero();
          W(p, i) = r(j) / (r(i) + r(j));
          W(p, j) = r(i) / (r(i) + r(j));
          return;
        }
      } else {
        t(i) = (r(i) * r(j) - D) / (2 * A);
      }
    }
    for (Index i = 0; i < m; ++i) W(p, i) = (t((i + m - 1) % m) + t(i)) / r(i);
    W.row(p) /= W.row(p).sum();
  }, 256);
  return W;
}

Cage starCage(int size) {
  const int m = 24;
  Points C(m, 2);
  for (int i = 0; i < m; ++i) {
    const double a = 2 * std::numbers::pi * i / m, r = (i % 2 ? 0.3 : 0.45) * size;
    C.row(i) << size / 2.0 + r * std::cos(a), size / 2.0 + r * std::sin(a);
  }
  return Cage::polygon(C);
}

Pose somePose(Index m, int k) {
  Pose pose = restPose(m);
  for (Index i = 0; i < m; i += 3) pose[std::size_t(i)] = {Vec2(10.0 * std::sin(i + k), 7.0 * std::cos(i - k)), 0.05 * k};
  return pose;
}

Image texture(int n) {
  Image img(n, n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = ((x / 32 + y / 32) % 2) ? 230 : 30, p[1] = std::uint8_t(x), p[2] = std::uint8_t(y), p[3] = 255;
    }
  return img;
}

struct Setup {
  WarpMesh mesh;
  CompactWeightsReport compact;
  Setup(int size, double spacing, OutsideMode outside = OutsideMode::Deform, bool followCage = true, bool repairFolds = true)
      : mesh(size, size, starCage(size), WarpMeshOptions{spacing, 1e-3, outside, followCage, repairFolds}) {
    compact = mesh.setWeights(meanValue(mesh.cage().C, mesh.restVertices()));
  }
};

/// New pose on a 1024×1024 image: f = Σ w_i T_i x at every warp-mesh vertex (+ det J per triangle).
void BM_DeformWarpMesh1MP(benchmark::State& state) {
  static Setup s4(1024, 4.0), s2(1024, 2.0);
  Setup& s = state.range(1) == 2 ? s2 : s4;
  ScopedThreadCount threads(int(state.range(0)));
  int k = 0;
  DeformReport rep;
  for (auto _ : state) rep = s.mesh.deform(somePose(s.mesh.cage().size(), ++k));
  state.counters["vertices"] = double(s.mesh.restVertices().rows());
  state.counters["nnz/vertex"] = s.compact.meanPerVertex;
  state.counters["compactMB"] = s.compact.compactBytes / 1e6;
  state.counters["denseMB"] = s.compact.denseBytes / 1e6;
}
BENCHMARK(BM_DeformWarpMesh1MP)->ArgNames({"threads", "spacing"})->Args({1, 4})->Args({2, 4})->Args({2, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

/// Building the warp mesh of a 1024×1024 image (spacing 4: 66k vertices): the grid alone (deform)
/// vs the grid plus the pinned mode's exterior weights (factorization + 24 right-hand sides);
/// pinned = 2: the mesh that follows the cage (WarpMeshOptions::followCage).
void BM_BuildWarpMesh1MP(benchmark::State& state) {
  const Cage cage = starCage(1024);
  WarpMeshOptions o;
  o.outside = state.range(1) >= 1 ? OutsideMode::Pinned : OutsideMode::Deform;
  o.followCage = state.range(1) == 2;
  ScopedThreadCount threads(int(state.range(0)));
  for (auto _ : state) {
    WarpMesh mesh(1024, 1024, cage, o);
    benchmark::DoNotOptimize(mesh.restVertices().data());
    if (const ExteriorWeights* e = mesh.exteriorWeights()) {
      state.counters["unknowns"] = double(e->report.unknowns);
      state.counters["factor_ms"] = 1e3 * e->report.factorSeconds;
      state.counters["solve_ms"] = 1e3 * e->report.solveSeconds;
    }
  }
}
BENCHMARK(BM_BuildWarpMesh1MP)->ArgNames({"threads", "pinned"})->Args({2, 0})->Args({1, 1})->Args({2, 1})->Args({2, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

/// New pose on a 1024×1024 image in the pinned mode (m + 1 columns with the anchor, the mesh
/// that follows the cage), without and with the fold repair. somePose turns controls by 0.05·k
/// rad, so later poses fold (counters: mean per pose of the triangles the harmonic extension
/// folded, of those left after the repair, and of the repair's milliseconds).
void BM_DeformPinned1MP(benchmark::State& state) {
  static Setup repaired(1024, 4.0, OutsideMode::Pinned, true, true), plain(1024, 4.0, OutsideMode::Pinned, true, false);
  Setup& s = state.range(1) ? repaired : plain;
  ScopedThreadCount threads(int(state.range(0)));
  int k = 0;
  double folds = 0.0, left = 0.0, ms = 0.0;
  for (auto _ : state) {
    const DeformReport r = s.mesh.deform(somePose(s.mesh.cage().size(), ++k));
    folds += double(r.harmonicFolds);
    left += double(r.repairedFolds);
    ms += 1e3 * r.repairSeconds;
  }
  state.counters["nnz/vertex"] = s.compact.meanPerVertex;
  state.counters["harmonic_folds"] = benchmark::Counter(folds, benchmark::Counter::kAvgIterations);
  state.counters["folds_left"] = benchmark::Counter(left, benchmark::Counter::kAvgIterations);
  state.counters["repair_ms"] = benchmark::Counter(ms, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_DeformPinned1MP)->ArgNames({"threads", "repair"})->Args({2, 0})->Args({2, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

/// Same, for one pose that pushes control 0 of the star (52 px from the right border) 40 px
/// towards the border and turns it (repair = 1: with the fold repair).
void BM_DeformPinnedTowardsTheBorder1MP(benchmark::State& state) {
  static Setup repaired(1024, 4.0, OutsideMode::Pinned, true, true), plain(1024, 4.0, OutsideMode::Pinned, true, false);
  Setup& s = state.range(1) ? repaired : plain;
  ScopedThreadCount threads(int(state.range(0)));
  Pose pose = restPose(s.mesh.cage().size());
  pose[0] = {Vec2(40.0, 10.0), 0.3};
  DeformReport rep;
  for (auto _ : state) rep = s.mesh.deform(pose);
  state.counters["harmonic_folds"] = double(rep.harmonicFolds);
  state.counters["folds_left"] = double(rep.repairedFolds);
  state.counters["repair_ms"] = 1e3 * rep.repairSeconds;
  state.counters["moved"] = double(rep.repairVertices);
}
BENCHMARK(BM_DeformPinnedTowardsTheBorder1MP)->ArgNames({"threads", "repair"})->Args({2, 0})->Args({2, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

/// A live drag in the pinned mode: control 0 of the star (52 px from the right border) goes 70 px
/// towards the border and past it (at 51 px) and back, 1 px per frame, turning up to 0.3 rad;
/// live = 1 repairs each frame with DeformPass::Live (from the previous picture, a smaller
/// budget), live = 0 with the full repair (what every frame cost before the Live pass). Counters: per frame, the harmonic extension's
/// folds, those left, the repair's milliseconds, and the frames that started from the previous one.
void BM_DragPinnedPastTheBorder1MP(benchmark::State& state) {
  static Setup s(1024, 4.0, OutsideMode::Pinned, true, true);
  const DeformPass pass = state.range(1) ? DeformPass::Live : DeformPass::Final;
  ScopedThreadCount threads(int(state.range(0)));
  Pose pose = restPose(s.mesh.cage().size());
  int frame = 0;
  double folds = 0.0, left = 0.0, ms = 0.0, warm = 0.0;
  for (auto _ : state) {
    const int k = frame++ % 140, d = k <= 70 ? k : 140 - k;
    pose[0] = {Vec2(double(d), 0.25 * d), 0.3 * d / 70.0};
    const DeformReport r = s.mesh.deform(pose, pass);
    folds += double(r.harmonicFolds);
    left += double(r.repairedFolds);
    ms += 1e3 * r.repairSeconds;
    warm += r.repairWarmStart ? 1.0 : 0.0;
  }
  state.counters["harmonic_folds"] = benchmark::Counter(folds, benchmark::Counter::kAvgIterations);
  state.counters["folds_left"] = benchmark::Counter(left, benchmark::Counter::kAvgIterations);
  state.counters["repair_ms"] = benchmark::Counter(ms, benchmark::Counter::kAvgIterations);
  state.counters["warm"] = benchmark::Counter(warm, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_DragPinnedPastTheBorder1MP)->ArgNames({"threads", "live"})->Args({2, 0})->Args({2, 1})->Iterations(140)
    ->Unit(benchmark::kMillisecond)->UseRealTime();

/// Full-resolution export of a 2048×2048 image: rasterize the deformed mesh (spacing 4).
void BM_Export2048(benchmark::State& state) {
  static Setup s(2048, 4.0);
  static const Image src = texture(2048);
  ScopedThreadCount threads(int(state.range(0)));
  s.mesh.deform(somePose(s.mesh.cage().size(), 3));
  RasterOptions opt;
  opt.supersample = int(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(s.mesh.render(src, opt).rgba.data());
  state.counters["triangles"] = double(s.mesh.triangles().size());
}
BENCHMARK(BM_Export2048)->ArgNames({"threads", "supersample"})->Args({1, 1})->Args({2, 1})->Args({2, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
