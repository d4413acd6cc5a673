#include "kc/core/exterior_untangle.h"

#include "kc/core/exterior_relax.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "triangle_area.h"

namespace kc {

Vec2 exteriorOutwardAt(const ExteriorRepairFrame& f, const Vec2& p) {
  return {p.x() == f.x0 ? -1.0 : (p.x() == f.x1 ? 1.0 : 0.0), p.y() == f.y0 ? -1.0 : (p.y() == f.y1 ? 1.0 : 0.0)};
}

namespace {

using detail::signedArea2;

double jacobian(const Points& P, const std::array<int, 3>& t, double restArea) { return 0.5 * signedArea2(P, t) / restArea; }

/// The continuation widens its region where a triangle this squeezed (det J below it) reaches the
/// region's edge, so that the relaxation can spread the squeeze further out. A larger threshold
/// leaves larger smallest det J and moves the border less.
constexpr double kSqueezed = 0.3;

/// det J of a star triangle as an affine function of its vertex v's position p: n·p + e.
struct AffineJacobian {
  double nx, ny, e;
  double at(double x, double y) const { return nx * x + ny * y + e; }
};

/// The mesh data one repair works on.
class Repair {
 public:
  /// start, entry, P: #V + ghosts rows (ghost rows fixed); rest: #V rows (the border's rest
  /// positions); restArea: #exteriorTriangles, ghostArea: #ghosts.
  /// free: the topology's free flags, less the vertices this repair holds (see forcedFolds).
  Repair(const Points& start, const Points& entry, Points& P, const Points& rest, const Triangles& T,
         const ExteriorRepairTopology& topo, const std::vector<std::uint8_t>& free, Index exteriorTriangles,
         const Eigen::VectorXd& restArea, const Eigen::VectorXd& ghostArea, const ExteriorRepairOptions& o)
      : R(start),
        E(entry),
        P(P),
        rest(rest),
        T(T),
        topo(topo),
        free(free),
        nt(exteriorTriangles),
        A(restArea),
        GA(ghostArea),
        o(o),
        inRegion(std::size_t(P.rows()), 0),
        seen(std::size_t(P.rows()), 0),
        seenTriangle(std::size_t(exteriorTriangles) + topo.ghosts.size(), 0) {}

  const std::array<int, 3>& tri(Index t) const { return t < nt ? T[std::size_t(t)] : topo.ghosts[std::size_t(t - nt)]; }
  double area(Index t) const { return t < nt ? A(t) : GA(t - nt); }

  /// Adds the free vertices of the triangles in `bad` and `rings` rings of free neighbours.
  void grow(const std::vector<Index>& bad) {
    std::vector<int> front;
    for (Index t : bad)
      for (int v : tri(t))
        if (free[std::size_t(v)] && !inRegion[std::size_t(v)]) add(v, front);
    for (int ring = 0; ring < o.rings && !front.empty(); ++ring) {
      std::vector<int> next;
      for (int v : front)
        for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k)
          for (int u : tri(topo.around[std::size_t(k)]))
            if (free[std::size_t(u)] && !inRegion[std::size_t(u)]) add(u, next);
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
        if (jacobian(P, tri(t), area(t)) > threshold) continue;
        bad.push_back(t);
        if (outside)
          for (int u : tri(t))
            if (free[std::size_t(u)] && !inRegion[std::size_t(u)]) {
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
      const auto consider = [&](double x, double y) {
        if (!std::isfinite(x) || !std::isfinite(y) || !allowed(v, x, y)) return;
        const double value = starMin(x, y);
        if (value > best) best = value, bx = x, by = y;
      };
      const std::size_t n = fs.size();
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
          for (std::size_t l = j + 1; l < n; ++l) {
            // f_i = f_j = f_l: two linear equations in p.
            const double a11 = fs[i].nx - fs[j].nx, a12 = fs[i].ny - fs[j].ny, r1 = fs[j].e - fs[i].e;
            const double a21 = fs[i].nx - fs[l].nx, a22 = fs[i].ny - fs[l].ny, r2 = fs[l].e - fs[i].e;
            const double det = a11 * a22 - a12 * a21;
            if (std::abs(det) < 1e-14 * (std::abs(a11 * a22) + std::abs(a12 * a21)) || det == 0.0) continue;
            consider((r1 * a22 - a12 * r2) / det, (a11 * r2 - r1 * a21) / det);
          }
      if (free[std::size_t(v)] == 2) {
        // A border vertex: the optimum may lie on the border line p0 + t·τ, where f_i = f_j.
        const Vec2 p0 = rest.row(v).transpose(), tau = tangent(v);
        consider(p0.x(), p0.y());
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t j = i + 1; j < n; ++j) {
            const double si = fs[i].nx * tau.x() + fs[i].ny * tau.y(), sj = fs[j].nx * tau.x() + fs[j].ny * tau.y();
            if (si == sj) continue;
            const double t = (fs[j].at(p0.x(), p0.y()) - fs[i].at(p0.x(), p0.y())) / (si - sj);
            consider(p0.x() + t * tau.x(), p0.y() + t * tau.y());
          }
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
        for (int u : tri(topo.around[std::size_t(k)]))
          if (!inRegion[std::size_t(u)]) toTarget(u);
  }

  /// Per connected part of the region (vertices sharing a triangle): back to the harmonic
  /// positions where the repair left a folded triangle around it (a fold no placement removes: the
  /// cage pushed past the border or over itself; the continuation then spent its budget spreading
  /// the squeeze, and kept moved would drag the background and the border for one fold fewer).
  /// Returns the vertices kept moved.
  Index revertWhereFolded() {
    std::vector<int> part;
    std::vector<std::uint8_t> done(region.size(), 0);
    Index kept = 0;
    for (std::size_t r0 = 0; r0 < region.size(); ++r0) {
      if (done[r0]) continue;
      part.assign(1, region[r0]);
      done[r0] = 1;
      for (std::size_t q = 0; q < part.size(); ++q)
        for (Index k = topo.start[std::size_t(part[q])]; k < topo.start[std::size_t(part[q]) + 1]; ++k)
          for (int u : tri(topo.around[std::size_t(k)]))
            if (const std::uint32_t r = inRegion[std::size_t(u)]; r && !done[r - 1]) {
              done[r - 1] = 1;
              part.push_back(u);
            }
      ++stamp;
      bool folds = false;
      for (std::size_t q = 0; q < part.size() && !folds; ++q)
        for (Index k = topo.start[std::size_t(part[q])]; k < topo.start[std::size_t(part[q]) + 1] && !folds; ++k) {
          const Index t = topo.around[std::size_t(k)];
          folds = !mark(t) && !(jacobian(P, tri(t), area(t)) > 0.0);
        }
      if (folds) {
        for (int v : part) P.row(v) = E.row(v);
      } else {
        kept += Index(part.size());
        for (int v : part) keptBorder += free[std::size_t(v)] == 2;
      }
    }
    return kept;
  }

  /// The positions of the region and its neighbours at fraction s.
  struct Snapshot {
    double s = 0.0;
    std::vector<std::pair<int, Vec2>> at;
  };
  Snapshot snapshot() {
    Snapshot k{s, {}};
    ++stamp;
    for (int v : region)
      for (Index q = topo.start[std::size_t(v)]; q < topo.start[std::size_t(v) + 1]; ++q)
        for (int u : tri(topo.around[std::size_t(q)]))
          if (seen[std::size_t(u)] != stamp) {
            seen[std::size_t(u)] = stamp;
            k.at.push_back({u, P.row(u).transpose()});
          }
    return k;
  }
  /// Back to a snapshot; vertices that joined the region since start at their targets.
  void restore(const Snapshot& k) {
    s = k.s;
    ++stamp;
    for (const auto& [u, p] : k.at) {
      P.row(u) = p.transpose();
      seen[std::size_t(u)] = stamp;
    }
    for (int v : region)
      if (seen[std::size_t(v)] != stamp) toTarget(v);
    placeNeighbours();
  }

  std::vector<int> region;
  double s = 0.0;  // continuation fraction
  Index keptBorder = 0;  // border vertices kept moved by revertWhereFolded

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
  /// A border vertex stays on the image's side of its border line or beyond it (n·(p − p0) ≥ 0).
  bool allowed(int v, double x, double y) const {
    if (free[std::size_t(v)] != 2) return true;
    const Vec2 n = exteriorOutwardAt(topo.frame, rest.row(v).transpose());
    return n.x() * (x - rest(v, 0)) + n.y() * (y - rest(v, 1)) >= -1e-9 * topo.spacing;
  }
  Vec2 tangent(int v) const {
    const Vec2 n = exteriorOutwardAt(topo.frame, rest.row(v).transpose());
    return {-n.y(), n.x()};
  }
  /// fs = det J of v's star triangles as affine functions of v's position.
  void star(int v) {
    fs.clear();
    for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k) {
      const Index t = topo.around[std::size_t(k)];
      const std::array<int, 3>& tr = tri(t);
      const int i = tr[0] == v ? 0 : (tr[1] == v ? 1 : 2);
      const int a = tr[std::size_t((i + 1) % 3)], b = tr[std::size_t((i + 2) % 3)];
      // 2·area(p, a, b) = cross(a − p, b − p) = cross(a, b) + p.x (a.y − b.y) + p.y (b.x − a.x)
      const double s = 0.5 / area(t);
      fs.push_back({s * (P(a, 1) - P(b, 1)), s * (P(b, 0) - P(a, 0)), s * (P(a, 0) * P(b, 1) - P(a, 1) * P(b, 0))});
    }
  }
  double starMin(double x, double y) const {
    double m = std::numeric_limits<double>::infinity();
    for (const AffineJacobian& f : fs) m = std::min(m, f.at(x, y));
    return m;
  }

  const Points& R;  // the continuation's start (rest, or an earlier result)
  const Points& E;
  Points& P;
  const Points& rest;
  const Triangles& T;
  const ExteriorRepairTopology& topo;
  const std::vector<std::uint8_t>& free;
  Index nt;
  const Eigen::VectorXd& A;
  const Eigen::VectorXd& GA;
  const ExteriorRepairOptions& o;

 public:
  std::vector<std::uint32_t> inRegion;  // 1-based index into region, 0 outside it

 private:
  std::vector<std::uint32_t> seen, seenTriangle;
  std::uint32_t stamp = 0;
  std::vector<AffineJacobian> fs;
};

}  // namespace

namespace {

/// The triangles among `folded` that fold because the cage's outline turns back: one of their
/// edges is a piece of the outline between two points on the cage (not free) whose deformed
/// direction opposes the next or previous piece of the same cage edge (collinear with it and in
/// the same direction at rest). The background triangle on such a piece folds wherever its free
/// vertex goes outside the deformed inside. (The field's weights along the cage are not linear; a
/// kernel field's interpolant can turn a piece a fraction of a pixel long over, next to a point
/// that it interpolates exactly.)
std::vector<Index> foldsOnATurnedPiece(const Points& rest, const Points& deformed, const Triangles& triangles,
                                       const ExteriorRepairTopology& topo, Index nt, const std::vector<Index>& folded) {
  const auto onCage = [&](int v) { return !topo.free[std::size_t(v)]; };
  const auto direction = [](const Points& P, int from, int to) -> Vec2 { return P.row(to) - P.row(from); };
  // Whether piece a→b runs against a piece b→x of the same cage edge (x among b's exterior neighbours).
  const auto turnedAt = [&](int a, int b) {
    const Vec2 r = direction(rest, a, b), d = direction(deformed, a, b);
    for (Index k = topo.start[std::size_t(b)]; k < topo.start[std::size_t(b) + 1]; ++k) {
      const Index t = topo.around[std::size_t(k)];
      if (t >= nt) continue;
      for (int x : triangles[std::size_t(t)]) {
        if (x == a || x == b || !onCage(x)) continue;
        const Vec2 rx = direction(rest, b, x);
        const bool sameEdge = r.dot(rx) > 0.0 && std::abs(r.x() * rx.y() - r.y() * rx.x()) <= 1e-9 * r.norm() * rx.norm();
        if (sameEdge && d.dot(direction(deformed, b, x)) < 0.0) return true;
      }
    }
    return false;
  };
  std::vector<Index> forced;
  for (const Index t : folded) {
    const std::array<int, 3>& tri = triangles[std::size_t(t)];
    for (int k = 0; k < 3; ++k) {
      const int a = tri[std::size_t(k)], b = tri[std::size_t((k + 1) % 3)];
      if (onCage(a) && onCage(b) && (turnedAt(a, b) || turnedAt(b, a))) {
        forced.push_back(t);
        break;
      }
    }
  }
  return forced;
}

/// The border ring of `rest` on `f`: border vertices in order around the frame (empty when two
/// border vertices coincide or a pair of ring neighbours is not an edge of `triangles`).
std::vector<int> borderRing(const Points& rest, const Triangles& triangles, const ExteriorRepairFrame& f) {
  const double w = f.x1 - f.x0, h = f.y1 - f.y0;
  std::vector<std::pair<double, int>> along;  // perimeter parameter, vertex
  for (Index v = 0; v < rest.rows(); ++v) {
    const double x = rest(v, 0), y = rest(v, 1);
    if (y == f.y0 && x >= f.x0 && x <= f.x1) along.push_back({x - f.x0, int(v)});
    else if (x == f.x1 && y >= f.y0 && y <= f.y1) along.push_back({w + (y - f.y0), int(v)});
    else if (y == f.y1 && x >= f.x0 && x <= f.x1) along.push_back({w + h + (f.x1 - x), int(v)});
    else if (x == f.x0 && y >= f.y0 && y <= f.y1) along.push_back({2 * w + h + (f.y1 - y), int(v)});
  }
  std::sort(along.begin(), along.end());
  std::vector<int> ring;
  for (std::size_t k = 0; k < along.size(); ++k) {
    if (k > 0 && along[k].first == along[k - 1].first) return {};
    ring.push_back(along[k].second);
  }
  if (ring.size() < 4) return {};
  // Ring neighbours must be mesh edges (the mesh covers the rectangle).
  std::vector<int> position(std::size_t(rest.rows()), -1);
  for (std::size_t k = 0; k < ring.size(); ++k) position[std::size_t(ring[k])] = int(k);
  const int n = int(ring.size());
  std::vector<std::uint8_t> edge(ring.size(), 0);  // edge k: ring[k] – ring[k + 1]
  for (const auto& t : triangles)
    for (int e = 0; e < 3; ++e) {
      const int a = position[std::size_t(t[std::size_t(e)])], b = position[std::size_t(t[std::size_t((e + 1) % 3)])];
      if (a < 0 || b < 0) continue;
      if ((a + 1) % n == b) edge[std::size_t(a)] = 1;
      if ((b + 1) % n == a) edge[std::size_t(b)] = 1;
    }
  for (std::uint8_t e : edge)
    if (!e) return {};
  return ring;
}

}  // namespace

ExteriorRepairTopology exteriorRepairTopology(const Points& rest, const Triangles& triangles, Index exteriorTriangles,
                                              const std::vector<std::uint8_t>& movable, const ExteriorRepairFrame* frame) {
  const Index nt = std::min<Index>(exteriorTriangles, Index(triangles.size()));
  const Index vertices = rest.rows();
  ExteriorRepairTopology g;
  if (frame) {
    g.frame = *frame;
    g.ring = borderRing(rest, triangles, *frame);
  }
  const Index ng = Index(g.ring.size());
  for (Index k = 0; k < ng; ++k) {
    const int a = g.ring[std::size_t(k)], b = g.ring[std::size_t((k + 1) % ng)];
    const int ga = int(vertices + k), gb = int(vertices + (k + 1) % ng);
    g.ghosts.push_back({a, b, gb});
    g.ghosts.push_back({a, gb, ga});
    g.outward.push_back(exteriorOutwardAt(g.frame, rest.row(a).transpose()));
    g.spacing = std::max(g.spacing, (rest.row(b) - rest.row(a)).norm());
  }
  const Index all = nt + Index(g.ghosts.size());
  const auto triangle = [&](Index t) -> const std::array<int, 3>& { return t < nt ? triangles[std::size_t(t)] : g.ghosts[std::size_t(t - nt)]; };
  g.start.assign(std::size_t(vertices + ng) + 1, 0);
  g.around.resize(std::size_t(all) * 3);
  for (Index t = 0; t < all; ++t)
    for (int v : triangle(t)) ++g.start[std::size_t(v) + 1];
  g.free.assign(std::size_t(vertices + ng), 0);
  for (Index v = 0; v < vertices; ++v) {
    if (!movable[std::size_t(v)] || g.start[std::size_t(v) + 1] == 0) continue;
    const double x = rest(v, 0), y = rest(v, 1);
    if (!frame || !(x == frame->x0 || x == frame->x1 || y == frame->y0 || y == frame->y1)) {
      g.free[std::size_t(v)] = 1;
      continue;
    }
    const Vec2 n = exteriorOutwardAt(g.frame, rest.row(v).transpose());
    g.free[std::size_t(v)] = ng > 0 && (n.x() == 0.0) != (n.y() == 0.0) ? 2 : 0;  // corners stay
  }
  // A free vertex's star must be closed: no triangle of the inside may use it.
  for (std::size_t t = std::size_t(nt); t < triangles.size(); ++t)
    for (int v : triangles[t]) g.free[std::size_t(v)] = 0;
  for (Index v = 0; v < vertices + ng; ++v) g.start[std::size_t(v) + 1] += g.start[std::size_t(v)];
  std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
  for (Index t = 0; t < all; ++t)
    for (int v : triangle(t)) g.around[std::size_t(fill[std::size_t(v)]++)] = t;
  return g;
}

ExteriorRepairReport repairExteriorFolds(const Points& rest, Points& deformed, const Triangles& triangles, const ExteriorRepairTopology& topology,
                                         Index exteriorTriangles, const Eigen::VectorXd& restArea,
                                         const ExteriorRepairOptions& options, const ExteriorRepairStart& start) {
  ExteriorRepairReport rep;
  const Index nt = std::min<Index>(exteriorTriangles, Index(triangles.size()));
  std::vector<Index> bad, folded;
  for (Index t = 0; t < nt; ++t) {
    const double j = jacobian(deformed, triangles[std::size_t(t)], restArea(t));
    if (!(j > options.minJacobian)) bad.push_back(t);
    if (!(j > 0.0)) folded.push_back(t);
  }
  rep.foldedBefore = Index(folded.size());
  if (rep.foldedBefore == 0) return rep;  // a pose that folds nothing is left as it is
  // Folds the turned-over outline forces stay as the harmonic map put them, their vertices held:
  // the repair neither grows its region from them nor counts them against the parts it untangles.
  const std::vector<Index> forced = foldsOnATurnedPiece(rest, deformed, triangles, topology, nt, folded);
  rep.foldedForced = Index(forced.size());
  std::vector<std::uint8_t> held;
  if (!forced.empty()) {
    held = topology.free;
    for (const Index t : forced)
      for (int v : triangles[std::size_t(t)]) held[std::size_t(v)] = 0;
    std::erase_if(bad, [&](Index t) { return std::binary_search(forced.begin(), forced.end(), t); });
  }
  if (rep.foldedForced == rep.foldedBefore) {
    rep.foldedAfter = rep.foldedBefore;
    return rep;
  }
  // The ghost ring at distance G outside the frame: past the farthest harmonic position, plus a margin.
  const Index nv = deformed.rows(), ng = Index(topology.ring.size());
  const ExteriorRepairFrame& f = topology.frame;
  double overshoot = 0.0;
  if (ng > 0)
    for (Index v = 0; v < nv; ++v)
      overshoot = std::max({overshoot, f.x0 - deformed(v, 0), deformed(v, 0) - f.x1, f.y0 - deformed(v, 1), deformed(v, 1) - f.y1});
  const double G = overshoot + std::max(16.0 * topology.spacing, 0.25 * std::max(f.x1 - f.x0, f.y1 - f.y0));
  const auto extend = [&](const Points& top) {
    Points X(nv + ng, 2);
    X.topRows(nv) = top;
    for (Index k = 0; k < ng; ++k) X.row(nv + k) = rest.row(topology.ring[std::size_t(k)]) + G * topology.outward[std::size_t(k)].transpose();
    return X;
  };
  const Points entry = extend(deformed);  // the harmonic positions: the continuation's end and the fallback
  const bool warm = start.positions && start.positions->rows() == nv;
  rep.warmStart = warm;
  const Points restX = extend(rest), from = warm ? extend(*start.positions) : restX;
  Points P = entry;
  Eigen::VectorXd ghostArea(Index(topology.ghosts.size()));
  for (Index k = 0; k < ghostArea.size(); ++k) ghostArea(k) = 0.5 * signedArea2(restX, topology.ghosts[std::size_t(k)]);
  Repair r(from, entry, P, rest, triangles, topology, forced.empty() ? topology.free : held, nt, restArea, ghostArea, options);
  r.grow(bad);  // at s = 0: the region at the start positions
  r.placeNeighbours();
  if (r.region.empty()) {
    rep.foldedAfter = rep.foldedBefore;
    return rep;
  }
  // Adaptive continuation under a barrier: each step moves the region by its harmonic increment
  // and its neighbours to their targets; a step that folds a region triangle is taken back and
  // halved (down to 1/16 of the first); a step that folds none is relaxed (the symmetric Dirichlet
  // energy of exterior_relax.h, which grows without bound as a triangle degenerates, so the
  // squeeze spreads instead of collapsing triangles and nothing folds), and the next may double
  // (up to 1/steps). Where a squeezed triangle (det J < kSqueezed) reaches the region's edge, the
  // region grows. Only a step that still folds at the smallest size is untangled (the max–min
  // moves). The work is budgeted (ExteriorRepairOptions::budget); once spent, the last step goes
  // to s = 1.
  const double ds0 = 1.0 / std::max(1, warm ? options.warmSteps : options.steps), dsMin = ds0 / 16.0;
  const double budget = options.budget * std::lround(1.0 / ds0) * options.maxSweeps * double(r.region.size());
  double visits = 0.0;
  double ds = ds0;
  while (r.s < 1.0) {
    const bool last = visits >= budget;
    const double next = last || r.s + ds >= 1.0 - 1e-12 ? 1.0 : r.s + ds;
    const Repair::Snapshot before = r.snapshot();
    r.advance(next);
    if (!r.badAround(0.0, nullptr).empty()) {
      if (!last && next - before.s > dsMin * 1.5) {
        r.restore(before);
        ds = 0.5 * (next - before.s);
        ++rep.retries;
        continue;
      }
      for (int sweep = 0; sweep < options.maxSweeps; ++sweep) {
        ++rep.sweeps;
        visits += double(r.region.size());
        const int improved = r.untangleSweep();
        std::vector<Index> reach;
        if (r.badAround(options.minJacobian, &reach).empty()) break;
        if (!reach.empty()) {  // a fold pushed to the region's edge: widen the region
          r.grow(reach);
          r.placeNeighbours();
        } else if (improved == 0) {
          break;  // nothing the free vertices can still do at this step
        }
      }
    }
    if (options.stepRelaxSweeps > 0) {  // (a region the untangling left folded is not relaxed: its energy is infinite)
      const ExteriorRelaxReport relaxed = relaxExteriorRegion(restX, P, triangles, nt, topology, r.region, options.stepRelaxSweeps);
      visits += double(r.region.size()) * relaxed.sweeps;
    }
    std::vector<Index> reach;
    r.badAround(kSqueezed, &reach);
    if (!reach.empty()) {
      r.grow(reach);
      r.placeNeighbours();
    }
    ds = std::min(ds0, 2.0 * (next - before.s));
  }
  if (options.relaxSweeps > 0 && r.badAround(0.0, nullptr).empty())
    rep.relaxSweeps = relaxExteriorRegion(restX, P, triangles, nt, topology, r.region, options.relaxSweeps).sweeps;
  rep.regionVertices = r.revertWhereFolded();
  rep.borderVertices = r.keptBorder;
  deformed = P.topRows(nv);
  for (Index t = 0; t < nt; ++t)
    if (!(jacobian(deformed, triangles[std::size_t(t)], restArea(t)) > 0.0)) {
      ++rep.foldedAfter;
      const auto& tri = triangles[std::size_t(t)];
      rep.foldedFixed += !topology.free[std::size_t(tri[0])] && !topology.free[std::size_t(tri[1])] && !topology.free[std::size_t(tri[2])];
    }
  return rep;
}

}  // namespace kc
