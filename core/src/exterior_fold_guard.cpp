#include "kc/core/exterior_fold_guard.h"

#include <algorithm>
#include <array>

namespace kc {
namespace {

/// Factor per round on the scales of a folded triangle's vertices (0.5 held back about twice as
/// many vertices on the bundled poses, for the same result).
constexpr double kShrink = 0.75;
/// A held-back region's scale rises from 0 to 1 over at least kRampLengths times the displacement.
constexpr double kRampLengths = 2.0;
/// Ramps (each followed by fold rounds) per deform; the ramps after the first change little.
constexpr int kRampPasses = 3;
/// A scale below this is set to 0 (the vertex at rest) and no longer halved.
constexpr double kAtRest = 1.0 / 1024.0;
/// Vertices next to the cage are halved once a folded triangle's other vertices are below this.
constexpr double kFarFirstDown = 1.0 / 64.0;

double jacobian(const Points& P, const std::array<int, 3>& t, double restArea) {
  const double ax = P(t[1], 0) - P(t[0], 0), ay = P(t[1], 1) - P(t[0], 1);
  const double bx = P(t[2], 0) - P(t[0], 0), by = P(t[2], 1) - P(t[0], 1);
  return 0.5 * (ax * by - ay * bx) / restArea;
}

}  // namespace

FoldGuardTopology foldGuardTopology(const Triangles& triangles, Index guardedTriangles, Index vertices) {
  const Index nt = std::min<Index>(guardedTriangles, Index(triangles.size()));
  FoldGuardTopology g;
  g.start.assign(std::size_t(vertices) + 1, 0);
  g.around.resize(std::size_t(nt) * 3);
  for (Index t = 0; t < nt; ++t)
    for (int v : triangles[std::size_t(t)]) ++g.start[std::size_t(v) + 1];
  for (Index v = 0; v < vertices; ++v) g.start[std::size_t(v) + 1] += g.start[std::size_t(v)];
  std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
  for (Index t = 0; t < nt; ++t)
    for (int v : triangles[std::size_t(t)]) g.around[std::size_t(fill[std::size_t(v)]++)] = t;
  return g;
}

FoldGuardReport guardExteriorFolds(const Points& rest, Points& deformed, const Triangles& triangles,
                                   const FoldGuardTopology& topology, Index guardedTriangles,
                                   const Eigen::VectorXd& restArea, const std::vector<std::uint8_t>& movable,
                                   double minJacobian) {
  FoldGuardReport rep;
  const Index nt = std::min<Index>(guardedTriangles, Index(triangles.size()));
  std::vector<Index> bad;
  for (Index t = 0; t < nt; ++t)
    if (!(jacobian(deformed, triangles[std::size_t(t)], restArea(t)) > minJacobian)) bad.push_back(t);
  rep.foldedBefore = Index(bad.size());
  if (bad.empty()) return rep;

  const Index nv = rest.rows();
  const std::vector<Index>& start = topology.start;
  const std::vector<Index>& around = topology.around;
  const Points displacement = deformed - rest;
  std::vector<double> scale(std::size_t(nv), 1.0);
  std::vector<std::uint32_t> seenVertex(std::size_t(nv), 0), seenTriangle(std::size_t(nt), 0);
  std::uint32_t stamp = 0;
  std::vector<int> changed;
  // bad = the guarded triangles around the vertices in `changed` that are folded.
  const auto recheck = [&] {
    ++stamp;
    bad.clear();
    for (int v : changed)
      for (Index k = start[std::size_t(v)]; k < start[std::size_t(v) + 1]; ++k) {
        const Index t = around[std::size_t(k)];
        if (seenTriangle[std::size_t(t)] == stamp) continue;
        seenTriangle[std::size_t(t)] = stamp;
        if (!(jacobian(deformed, triangles[std::size_t(t)], restArea(t)) > minJacobian)) bad.push_back(t);
      }
  };
  const auto setScale = [&](int v, double s) {
    scale[std::size_t(v)] = s;
    deformed.row(v) = rest.row(v) + s * displacement.row(v);
  };
  // Rounds until no guarded triangle is folded. Every round scales at least one scale that is
  // ≥ kAtRest down, or ends: a bounded number of rounds.
  const auto settle = [&] {
    while (!bad.empty()) {
      ++rep.rounds;
      ++stamp;
      changed.clear();
      for (Index t : bad) {
        // Vertices away from the cage first, so the background stays attached to the cage; the
        // others once those are (almost) at rest.
        const std::array<int, 3>& tri = triangles[std::size_t(t)];
        const auto can = [&](int v, std::uint8_t cls) {
          return movable[std::size_t(v)] == cls && scale[std::size_t(v)] > 0.0 && displacement.row(v).squaredNorm() > 0.0;
        };
        const bool far = std::any_of(tri.begin(), tri.end(), [&](int v) { return can(v, 1) && scale[std::size_t(v)] > kFarFirstDown; });
        for (int v : tri) {
          if (!(can(v, 1) || (!far && can(v, 2))) || seenVertex[std::size_t(v)] == stamp) continue;
          seenVertex[std::size_t(v)] = stamp;
          changed.push_back(v);
        }
      }
      if (changed.empty()) return;  // the folded triangles left have no vertex the guard may move
      for (int v : changed) setScale(v, scale[std::size_t(v)] * kShrink < kAtRest ? 0.0 : kShrink * scale[std::size_t(v)]);
      recheck();
    }
  };
  // A held-back vertex holds its neighbours (away from the cage) back too, so the scale rises
  // smoothly: at w it is at most s_v + |w − v| / (kRampLengths·|d_w|), and the stretch the ramp
  // adds, |d|·|∇s|, stays below 1/kRampLengths (a shortest-path relaxation from every held-back
  // vertex). `changed` = the vertices it lowered.
  const auto ramp = [&] {
    changed.clear();
    std::vector<int> queue;
    for (Index v = 0; v < nv; ++v)
      if (scale[std::size_t(v)] < 1.0) queue.push_back(int(v));
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int v = queue[q];
      for (Index k = start[std::size_t(v)]; k < start[std::size_t(v) + 1]; ++k)
        for (int w : triangles[std::size_t(around[std::size_t(k)])]) {
          if (w == v || movable[std::size_t(w)] != 1) continue;
          const double d = displacement.row(w).norm();
          if (d == 0.0) continue;
          const double limit = scale[std::size_t(v)] + (rest.row(w) - rest.row(v)).norm() / (kRampLengths * d);
          if (!(limit < scale[std::size_t(w)])) continue;
          setScale(w, limit);
          queue.push_back(w);
          changed.push_back(w);
        }
    }
  };
  settle();
  for (int pass = 0; pass < kRampPasses; ++pass) {
    ramp();
    if (changed.empty()) break;
    recheck();
    settle();  // the last step is always a settle: nothing guarded is left folded
  }
  for (Index v = 0; v < nv; ++v)
    if (scale[std::size_t(v)] < 1.0) {
      ++rep.scaledVertices;
      rep.minScale = std::min(rep.minScale, scale[std::size_t(v)]);
    }
  return rep;
}

}  // namespace kc
