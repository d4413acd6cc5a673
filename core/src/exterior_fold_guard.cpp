#include "kc/core/exterior_fold_guard.h"

#include <algorithm>
#include <array>

namespace kc {
namespace {

/// Factor per round on the scales of a folded triangle's vertices (0.5 held back about twice as
/// many vertices on the bundled poses, for the same result).
constexpr double kShrink = 0.75;
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
  std::vector<int> changed;
  // Every round halves at least one scale that is ≥ kAtRest, or ends: a bounded number of rounds.
  for (std::uint32_t round = 1; !bad.empty(); ++round) {
    rep.rounds = int(round);
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
        if (!(can(v, 1) || (!far && can(v, 2))) || seenVertex[std::size_t(v)] == round) continue;
        seenVertex[std::size_t(v)] = round;
        changed.push_back(v);
      }
    }
    if (changed.empty()) break;  // the folded triangles left have no vertex the guard may move
    for (int v : changed) {
      double& s = scale[std::size_t(v)];
      s = s * kShrink < kAtRest ? 0.0 : kShrink * s;
      deformed.row(v) = rest.row(v) + s * displacement.row(v);
    }
    bad.clear();
    for (int v : changed)
      for (Index k = start[std::size_t(v)]; k < start[std::size_t(v) + 1]; ++k) {
        const Index t = around[std::size_t(k)];
        if (seenTriangle[std::size_t(t)] == round) continue;
        seenTriangle[std::size_t(t)] = round;
        if (!(jacobian(deformed, triangles[std::size_t(t)], restArea(t)) > minJacobian)) bad.push_back(t);
      }
  }
  for (Index v = 0; v < nv; ++v)
    if (scale[std::size_t(v)] < 1.0) {
      ++rep.scaledVertices;
      rep.minScale = std::min(rep.minScale, scale[std::size_t(v)]);
    }
  return rep;
}

}  // namespace kc
