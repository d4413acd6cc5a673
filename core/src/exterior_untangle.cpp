#include "kc/core/exterior_untangle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace kc {
namespace {

double jacobian(const Points& P, const std::array<int, 3>& t, double restArea) {
  const double ax = P(t[1], 0) - P(t[0], 0), ay = P(t[1], 1) - P(t[0], 1);
  const double bx = P(t[2], 0) - P(t[0], 0), by = P(t[2], 1) - P(t[0], 1);
  return 0.5 * (ax * by - ay * bx) / restArea;
}

/// det J of a star triangle as an affine function of its vertex v's position p: n·p + e.
struct AffineJacobian {
  double nx, ny, e;
  double at(double x, double y) const { return nx * x + ny * y + e; }
};

/// The mesh data one repair works on.
class Repair {
 public:
  Repair(const Points& rest, const Points& entry, Points& P, const Triangles& T, const ExteriorRepairTopology& topo,
         Index exteriorTriangles, const Eigen::VectorXd& restArea, const ExteriorRepairOptions& o)
      : R(rest), E(entry), P(P), T(T), topo(topo), nt(exteriorTriangles), A(restArea), o(o),
        inRegion(std::size_t(P.rows()), 0), seen(std::size_t(P.rows()), 0), seenTriangle(std::size_t(exteriorTriangles), 0) {}

  /// Adds the free vertices of the triangles in `bad` and `rings` rings of free neighbours.
  void grow(const std::vector<Index>& bad) {
    std::vector<int> front;
    for (Index t : bad)
      for (int v : T[std::size_t(t)])
        if (topo.free[std::size_t(v)] && !inRegion[std::size_t(v)]) add(v, front);
    for (int ring = 0; ring < o.rings && !front.empty(); ++ring) {
      std::vector<int> next;
      for (int v : front)
        for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k)
          for (int u : T[std::size_t(topo.around[std::size_t(k)])])
            if (topo.free[std::size_t(u)] && !inRegion[std::size_t(u)]) add(u, next);
      front = std::move(next);
    }
  }

  /// Exterior triangles with det J ≤ threshold around the region, and whether one of them has a
  /// free vertex outside the region (`outside`: those triangles).
  std::vector<Index> badAround(double threshold, std::vector<Index>* outside) {
    ++stamp;
    std::vector<Index> bad;
    for (int v : region)
      for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k) {
        const Index t = topo.around[std::size_t(k)];
        if (mark(t)) continue;
        if (jacobian(P, T[std::size_t(t)], A(t)) > threshold) continue;
        bad.push_back(t);
        if (outside)
          for (int u : T[std::size_t(t)])
            if (topo.free[std::size_t(u)] && !inRegion[std::size_t(u)]) {
              outside->push_back(t);
              break;
            }
      }
    return bad;
  }

  /// One untangling sweep; returns the number of vertices whose star minimum rose.
  int untangleSweep() {
    int improved = 0;
    for (int v : region) {
      star(v);
      const double now = starMin(P(v, 0), P(v, 1));
      if (now > o.minJacobian) continue;
      double bx = P(v, 0), by = P(v, 1), best = now;
      const std::size_t n = fs.size();
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
          for (std::size_t l = j + 1; l < n; ++l) {
            // f_i = f_j = f_l: two linear equations in p.
            const double a11 = fs[i].nx - fs[j].nx, a12 = fs[i].ny - fs[j].ny, r1 = fs[j].e - fs[i].e;
            const double a21 = fs[i].nx - fs[l].nx, a22 = fs[i].ny - fs[l].ny, r2 = fs[l].e - fs[i].e;
            const double det = a11 * a22 - a12 * a21;
            if (std::abs(det) < 1e-14 * (std::abs(a11 * a22) + std::abs(a12 * a21)) || det == 0.0) continue;
            const double x = (r1 * a22 - a12 * r2) / det, y = (a11 * r2 - r1 * a21) / det;
            if (!std::isfinite(x) || !std::isfinite(y)) continue;
            const double value = starMin(x, y);
            if (value > best) best = value, bx = x, by = y;
          }
      // (Where no placement removes a fold, this can spread it; repairExteriorFolds then falls
      // back to the harmonic map. Refusing such moves instead stalled the untangling of folds
      // that a coordinated move of several vertices removes.)
      if (best > now + 1e-9) {
        P(v, 0) = bx, P(v, 1) = by;
        ++improved;
      }
    }
    return improved;
  }

  /// One smoothing sweep of the correction δ = P − H towards its neighbour mean, never lowering a
  /// star's minimum below min(minJacobian, its current minimum).
  void smoothSweep() {
    for (int v : region) {
      ++stamp;
      double dx = 0.0, dy = 0.0;
      int count = 0;
      for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k)
        for (int u : T[std::size_t(topo.around[std::size_t(k)])]) {
          if (u == v || seen[std::size_t(u)] == stamp) continue;
          seen[std::size_t(u)] = stamp;
          ++count;
          dx += P(u, 0) - target(u, 0), dy += P(u, 1) - target(u, 1);
        }
      if (count == 0) continue;
      const double tx = target(v, 0) + dx / count, ty = target(v, 1) + dy / count;
      star(v);
      const double floor = std::min(o.minJacobian, starMin(P(v, 0), P(v, 1)));
      for (double s = 1.0; s > 1.0 / 64.0; s *= 0.5) {
        const double x = P(v, 0) + s * (tx - P(v, 0)), y = P(v, 1) + s * (ty - P(v, 1));
        if (starMin(x, y) >= floor) {
          P(v, 0) = x, P(v, 1) = y;
          break;
        }
      }
    }
  }

  /// The continuation's target of vertex u at the current fraction s: R + s (E − R).
  double target(int u, int axis) const { return s >= 1.0 ? E(u, axis) : R(u, axis) + s * (E(u, axis) - R(u, axis)); }
  void toTarget(int u) { P(u, 0) = target(u, 0), P(u, 1) = target(u, 1); }

  /// Moves to fraction `next`: region vertices by the increment of their harmonic displacement,
  /// the vertices next to the region (not in it) to their targets.
  void advance(double next) {
    const double ds = next - s;
    s = next;
    for (int v : region) P.row(v) += ds * (E.row(v) - R.row(v));
    placeNeighbours();
  }
  void placeNeighbours() {
    for (int v : region)
      for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k)
        for (int u : T[std::size_t(topo.around[std::size_t(k)])])
          if (!inRegion[std::size_t(u)]) toTarget(u);
  }

  /// Per connected part of the region (vertices sharing a triangle): back to the harmonic
  /// positions where the repair left more folded triangles around it than the harmonic map had
  /// (a fold no placement removes: the cage pushed past the border). Returns the vertices kept moved.
  Index revertWhereWorse() {
    std::vector<int> part;
    std::vector<std::uint8_t> done(region.size(), 0);
    Index kept = 0;
    for (std::size_t r0 = 0; r0 < region.size(); ++r0) {
      if (done[r0]) continue;
      part.assign(1, region[r0]);
      done[r0] = 1;
      for (std::size_t q = 0; q < part.size(); ++q)
        for (Index k = topo.start[std::size_t(part[q])]; k < topo.start[std::size_t(part[q]) + 1]; ++k)
          for (int u : T[std::size_t(topo.around[std::size_t(k)])])
            if (const std::uint32_t r = inRegion[std::size_t(u)]; r && !done[r - 1]) {
              done[r - 1] = 1;
              part.push_back(u);
            }
      ++stamp;
      Index before = 0, after = 0;
      for (int v : part)
        for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k) {
          const Index t = topo.around[std::size_t(k)];
          if (mark(t)) continue;
          before += !(jacobian(E, T[std::size_t(t)], A(t)) > 0.0);
          after += !(jacobian(P, T[std::size_t(t)], A(t)) > 0.0);
        }
      if (after > before)
        for (int v : part) P.row(v) = E.row(v);
      else
        kept += Index(part.size());
    }
    return kept;
  }

  std::vector<int> region;
  double s = 0.0;  // continuation fraction

 private:
  void add(int v, std::vector<int>& front) {
    region.push_back(v);
    toTarget(v);  // a new region vertex starts at its target
    inRegion[std::size_t(v)] = std::uint32_t(region.size());  // 1-based index into region
    front.push_back(v);
  }
  bool mark(Index t) {
    if (seenTriangle[std::size_t(t)] == stamp) return true;
    seenTriangle[std::size_t(t)] = stamp;
    return false;
  }
  /// fs = det J of v's star triangles as affine functions of v's position.
  void star(int v) {
    fs.clear();
    for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k) {
      const Index t = topo.around[std::size_t(k)];
      const std::array<int, 3>& tri = T[std::size_t(t)];
      const int i = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      const int a = tri[std::size_t((i + 1) % 3)], b = tri[std::size_t((i + 2) % 3)];
      // 2·area(p, a, b) = cross(a − p, b − p) = cross(a, b) + p.x (a.y − b.y) + p.y (b.x − a.x)
      const double s = 0.5 / A(t);
      fs.push_back({s * (P(a, 1) - P(b, 1)), s * (P(b, 0) - P(a, 0)), s * (P(a, 0) * P(b, 1) - P(a, 1) * P(b, 0))});
    }
  }
  double starMin(double x, double y) const {
    double m = std::numeric_limits<double>::infinity();
    for (const AffineJacobian& f : fs) m = std::min(m, f.at(x, y));
    return m;
  }

  const Points& R;
  const Points& E;
  Points& P;
  const Triangles& T;
  const ExteriorRepairTopology& topo;
  Index nt;
  const Eigen::VectorXd& A;
  const ExteriorRepairOptions& o;

 public:
  std::vector<std::uint32_t> inRegion;  // 1-based index into region, 0 outside it

 private:
  std::vector<std::uint32_t> seen, seenTriangle;
  std::uint32_t stamp = 0;
  std::vector<AffineJacobian> fs;
};

}  // namespace

ExteriorRepairTopology exteriorRepairTopology(const Triangles& triangles, Index exteriorTriangles, Index vertices,
                                              const std::vector<std::uint8_t>& movable) {
  const Index nt = std::min<Index>(exteriorTriangles, Index(triangles.size()));
  ExteriorRepairTopology g;
  g.start.assign(std::size_t(vertices) + 1, 0);
  g.around.resize(std::size_t(nt) * 3);
  for (Index t = 0; t < nt; ++t)
    for (int v : triangles[std::size_t(t)]) ++g.start[std::size_t(v) + 1];
  g.free.assign(std::size_t(vertices), 0);
  for (Index v = 0; v < vertices; ++v)
    g.free[std::size_t(v)] = movable[std::size_t(v)] && g.start[std::size_t(v) + 1] > 0 ? 1 : 0;
  // A free vertex's star must be closed: no triangle of the inside may use it.
  for (std::size_t t = std::size_t(nt); t < triangles.size(); ++t)
    for (int v : triangles[t]) g.free[std::size_t(v)] = 0;
  for (Index v = 0; v < vertices; ++v) g.start[std::size_t(v) + 1] += g.start[std::size_t(v)];
  std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
  for (Index t = 0; t < nt; ++t)
    for (int v : triangles[std::size_t(t)]) g.around[std::size_t(fill[std::size_t(v)]++)] = t;
  return g;
}

ExteriorRepairReport repairExteriorFolds(const Points& rest, Points& deformed, const Triangles& triangles, const ExteriorRepairTopology& topology,
                                         Index exteriorTriangles, const Eigen::VectorXd& restArea,
                                         const ExteriorRepairOptions& options) {
  ExteriorRepairReport rep;
  const Index nt = std::min<Index>(exteriorTriangles, Index(triangles.size()));
  std::vector<Index> bad;
  for (Index t = 0; t < nt; ++t) {
    const double j = jacobian(deformed, triangles[std::size_t(t)], restArea(t));
    if (!(j > options.minJacobian)) bad.push_back(t);
    if (!(j > 0.0)) ++rep.foldedBefore;
  }
  if (rep.foldedBefore == 0) return rep;  // a pose that folds nothing is left as it is
  const Points entry = deformed;  // the harmonic positions: the continuation's end and the fallback
  Repair r(rest, entry, deformed, triangles, topology, nt, restArea, options);
  r.grow(bad);  // at s = 0: the region at rest
  r.placeNeighbours();
  if (r.region.empty()) {
    rep.foldedAfter = rep.foldedBefore;
    return rep;
  }
  for (int step = 1; step <= options.steps; ++step) {
    r.advance(double(step) / options.steps);
    for (int sweep = 0; sweep < options.maxSweeps; ++sweep) {
      ++rep.sweeps;
      const int improved = r.untangleSweep();
      std::vector<Index> reach;
      const std::vector<Index> left = r.badAround(options.minJacobian, &reach);
      if (left.empty()) break;
      if (!reach.empty()) {  // a fold pushed to the region's edge: widen the region
        r.grow(reach);
        r.placeNeighbours();
      } else if (improved == 0) {
        break;  // nothing the free vertices can still do at this step
      }
    }
    for (int k = 0; k < options.smoothSweeps; ++k) r.smoothSweep();
  }
  rep.regionVertices = r.revertWhereWorse();
  for (Index t = 0; t < nt; ++t)
    if (!(jacobian(deformed, triangles[std::size_t(t)], restArea(t)) > 0.0)) {
      ++rep.foldedAfter;
      const auto& tri = triangles[std::size_t(t)];
      rep.foldedFixed += !topology.free[std::size_t(tri[0])] && !topology.free[std::size_t(tri[1])] && !topology.free[std::size_t(tri[2])];
    }
  return rep;
}

}  // namespace kc
