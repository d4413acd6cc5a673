#include "kc/core/cage.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "kc/core/spatial_grid.h"
#include <stdexcept>

namespace kc {
namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Orientation of c relative to the line a→b, with a tolerance relative to the lengths involved.
int orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double v = cross(b - a, c - a);
  const double scale = (b - a).norm() * (c - a).norm();
  const double eps = 1e-12 * scale;
  return v > eps ? 1 : (v < -eps ? -1 : 0);
}

bool onSegment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) - 1e-12 <= p.x() && p.x() <= std::max(a.x(), b.x()) + 1e-12 &&
         std::min(a.y(), b.y()) - 1e-12 <= p.y() && p.y() <= std::max(a.y(), b.y()) + 1e-12;
}

/// Closed segments a–b and c–d share at least one point.
bool segmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  if (o1 == 0 && onSegment(a, b, c)) return true;
  if (o2 == 0 && onSegment(a, b, d)) return true;
  if (o3 == 0 && onSegment(c, d, a)) return true;
  if (o4 == 0 && onSegment(c, d, b)) return true;
  return false;
}

std::string pointText(const Points& C, Index i) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "point %ld (%.6g, %.6g)", static_cast<long>(i), C(i, 0), C(i, 1));
  return buf;
}

}  // namespace

Cage Cage::polygon(const Points& C) {
  Cage cage;
  cage.C = C;
  cage.closed = true;
  const int m = static_cast<int>(C.rows());
  for (int i = 0; i < m; ++i) cage.edges.push_back({i, (i + 1) % m});
  return cage;
}

namespace {

/// Why edges e and f (indices into `edges`) cannot both be in a cage, or "" when they can.
std::string edgePairProblem(const Points& C, const std::vector<std::array<int, 2>>& edges, std::size_t e, std::size_t f) {
  const auto [a, b] = edges[e];
  const auto [c, d] = edges[f];
  const int shared = (a == c) + (a == d) + (b == c) + (b == d);
  const Vec2 A = C.row(a), B = C.row(b), Cc = C.row(c), D = C.row(d);
  if (shared >= 2) return "cage edges " + std::to_string(e) + " and " + std::to_string(f) + " are the same edge";
  if (shared == 1) {
    // Adjacent edges may only touch at their shared end: reject folding back onto each other.
    const int s = (a == c || a == d) ? a : b;
    const Vec2 S = C.row(s);
    const Vec2 u = ((a == s) ? B : A) - S, v = ((c == s) ? D : Cc) - S;
    if (std::abs(cross(u, v)) <= 1e-12 * u.norm() * v.norm() && u.dot(v) > 0)
      return "cage edges " + std::to_string(e) + " and " + std::to_string(f) + " overlap (the cage folds back on itself at " +
             pointText(C, s) + ")";
    return "";
  }
  if (segmentsIntersect(A, B, Cc, D))
    return "cage is self-intersecting: edge " + std::to_string(e) + " (points " + std::to_string(a) + "-" + std::to_string(b) +
           ") crosses edge " + std::to_string(f) + " (points " + std::to_string(c) + "-" + std::to_string(d) + ")";
  return "";
}

/// Pairs (e < f) of edges that may come within distance r of each other (every such pair is
/// listed; some listed pairs are farther apart), sorted. O(n log n) for cages whose edges are not
/// piled into one spot: every edge is registered in the grid cells within r of it (cells of about
/// the median edge length, kept in a sorted list, not a dense array), and only edges that share a
/// cell are paired. Two edges within r of each other share the cell of a point of one of them.
std::vector<std::pair<int, int>> nearEdgePairs(const Points& C, const std::vector<std::array<int, 2>>& edges, double r) {
  const std::size_t ne = edges.size();
  if (ne < 2) return {};
  std::vector<double> lengths(ne);
  double perimeter = 0.0;
  for (std::size_t e = 0; e < ne; ++e) perimeter += lengths[e] = (C.row(edges[e][0]) - C.row(edges[e][1])).norm();
  std::nth_element(lengths.begin(), lengths.begin() + std::ptrdiff_t(ne / 2), lengths.end());
  const double lo0 = C.col(0).minCoeff() - r, lo1 = C.col(1).minCoeff() - r;
  const double extent = std::max(C.col(0).maxCoeff() - lo0, C.col(1).maxCoeff() - lo1) + r;
  // About a dozen registrations per edge; cell indices stay far below 2^31 per axis.
  const double cell = std::max({lengths[ne / 2], perimeter / (4.0 * double(ne)), 2.0 * r, extent / 1e6, 1e-300});
  const double step = 0.5 * cell, pad = 0.25 * cell + r;
  std::vector<std::pair<std::int64_t, int>> entries;  // (cell, edge)
  entries.reserve(12 * ne);
  auto cellOf = [&](double x, double y) {
    const auto cx = static_cast<std::int64_t>(std::floor((x - lo0) / cell)) + 1;
    const auto cy = static_cast<std::int64_t>(std::floor((y - lo1) / cell)) + 1;
    return cy * (std::int64_t(1) << 31) + cx;
  };
  for (std::size_t e = 0; e < ne; ++e) {
    const Vec2 A = C.row(edges[e][0]), B = C.row(edges[e][1]);
    const auto steps = static_cast<std::int64_t>(std::ceil((B - A).norm() / step));
    for (std::int64_t k = 0; k <= steps; ++k) {
      const Vec2 p = steps ? Vec2(A + (B - A) * (double(k) / double(steps))) : A;
      // Every point within r of the edge near p lies within step/2 + r ≤ pad of p; the box of
      // half-side pad (at most 2 cells across) meets the cells of its corners and, when r is
      // large, the cells between them.
      const std::int64_t c0 = cellOf(p.x() - pad, p.y() - pad), c1 = cellOf(p.x() + pad, p.y() + pad);
      const std::int64_t row = std::int64_t(1) << 31;
      for (std::int64_t cy = c0 / row; cy <= c1 / row; ++cy)
        for (std::int64_t cx = c0 % row; cx <= c1 % row; ++cx) entries.emplace_back(cy * row + cx, static_cast<int>(e));
    }
  }
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i;
    while (j < entries.size() && entries[j].first == entries[i].first) ++j;
    for (std::size_t p = i; p < j; ++p)
      for (std::size_t q = p + 1; q < j; ++q) pairs.emplace_back(entries[p].second, entries[q].second);
    i = j;
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

/// The first problem among all pairs of edges (the lowest pair of indices), or "".
std::string firstEdgeProblem(const Points& C, const std::vector<std::array<int, 2>>& edges) {
  for (const auto& [e, f] : nearEdgePairs(C, edges, 0.0))
    if (std::string problem = edgePairProblem(C, edges, std::size_t(e), std::size_t(f)); !problem.empty()) return problem;
  return "";
}

}  // namespace

void validateCage(const Cage& cage) {
  const Index m = cage.size();
  const Points& C = cage.C;
  if (cage.closed && m < 3)
    throw std::invalid_argument("cage has " + std::to_string(m) + " points; a closed cage needs at least 3");
  if (!cage.closed && m < 2) throw std::invalid_argument("cage has fewer than 2 points");
  for (Index i = 0; i < m; ++i)
    if (!std::isfinite(C(i, 0)) || !std::isfinite(C(i, 1)))
      throw std::invalid_argument("cage point " + std::to_string(i) + " has a non-finite coordinate");
  const double extent = std::max(C.col(0).maxCoeff() - C.col(0).minCoeff(), C.col(1).maxCoeff() - C.col(1).minCoeff());
  if (!(extent > 0.0)) throw std::invalid_argument("cage points all coincide");
  {
    // Repeated points: neighbours within the tolerance, through a grid (O(m)).
    const double tol = 1e-9 * extent;
    const SpatialGrid grid(C, std::max(tol, 1e-300));
    Index first = -1, second = -1;
    for (Index i = 0; i < m && first < 0; ++i)
      grid.forEachWithin(C.row(i), tol, [&](Index j, double) {
        if (j > i && (first < 0 || j < second)) first = i, second = j;
      });
    if (first >= 0) throw std::invalid_argument("cage " + pointText(C, first) + " is repeated as point " + std::to_string(second));
  }
  bool collinear = true;
  for (Index i = 2; i < m && collinear; ++i)
    if (orient(C.row(0), C.row(1), C.row(i)) != 0) collinear = false;
  if (collinear && cage.closed) throw std::invalid_argument("cage points are all collinear (the cage has no area)");

  const auto edges = cageEdges(cage);
  if (!cage.closed && edges.empty()) throw std::invalid_argument("open cage has no edges");
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [a, b] = edges[e];
    if (a < 0 || b < 0 || a >= m || b >= m)
      throw std::invalid_argument("cage edge " + std::to_string(e) + " names a point that does not exist");
    if (a == b) throw std::invalid_argument("cage edge " + std::to_string(e) + " joins point " + std::to_string(a) + " to itself");
  }
  if (const std::string problem = firstEdgeProblem(C, edges); !problem.empty()) throw std::invalid_argument(problem);
}

CageGap narrowestGap(const Cage& cage, double below) {
  CageGap gap;
  gap.distance = std::numeric_limits<double>::infinity();
  const Points& C = cage.C;
  const auto edges = cageEdges(cage);
  for (const auto& [a, b] : edges)
    if (const double d = (C.row(a) - C.row(b)).norm(); d < below && d < gap.distance) gap = {d, a, b, -1, -1};
  for (const auto& [e, f] : nearEdgePairs(C, edges, below)) {
    const auto [a, b] = edges[std::size_t(e)];
    const auto [c, d] = edges[std::size_t(f)];
    if (a == c || a == d || b == c || b == d) continue;  // adjacent edges meet by design
    const double dist = segmentSegmentDistance(C.row(a), C.row(b), C.row(c), C.row(d));
    if (dist < below && dist < gap.distance) gap = {dist, -1, -1, e, f};
  }
  return gap;
}

std::vector<std::array<int, 2>> cageEdges(const Cage& cage) {
  if (!cage.closed || !cage.edges.empty()) return cage.edges;
  std::vector<std::array<int, 2>> e;
  const int m = static_cast<int>(cage.size());
  for (int i = 0; i < m; ++i) e.push_back({i, (i + 1) % m});
  return e;
}

bool isClosedPolygon(const Cage& cage) {
  if (!cage.closed) return false;
  const auto edges = cageEdges(cage);
  const int m = static_cast<int>(cage.size());
  if (static_cast<int>(edges.size()) != m) return false;
  for (int i = 0; i < m; ++i)
    if (edges[static_cast<std::size_t>(i)] != std::array<int, 2>{i, (i + 1) % m}) return false;
  return true;
}

double signedArea(const Points& C) {
  double a = 0.0;
  const Index m = C.rows();
  for (Index i = 0; i < m; ++i) {
    const Index j = (i + 1) % m;
    a += C(i, 0) * C(j, 1) - C(j, 0) * C(i, 1);
  }
  return 0.5 * a;
}

std::vector<char> loopEdgeFlags(const Cage& cage) {
  const std::vector<std::array<int, 2>> edges = cageEdges(cage);
  if (cage.closed && cage.edges.empty()) return std::vector<char>(edges.size(), 1);  // a polygon: one loop
  const int m = static_cast<int>(cage.size()), ne = static_cast<int>(edges.size());
  std::vector<std::vector<std::pair<int, int>>> adj(std::size_t(std::max(0, m)));  // (neighbour, edge)
  for (int e = 0; e < ne; ++e) {
    const auto [a, b] = edges[std::size_t(e)];
    if (a < 0 || b < 0 || a >= m || b >= m) continue;  // validateCage reports it
    adj[std::size_t(a)].emplace_back(b, e);
    adj[std::size_t(b)].emplace_back(a, e);
  }
  // Iterative DFS: low[v] = the earliest discovery time reachable from v's subtree by one back
  // edge; the tree edge parent→v is a bridge when low[v] > disc[parent].
  std::vector<int> disc(std::size_t(m), -1), low(std::size_t(m), 0);
  std::vector<char> bridge(std::size_t(ne), 0);
  int time = 0;
  struct Frame { int v, viaEdge; std::size_t next; };
  for (int root = 0; root < m; ++root) {
    if (disc[std::size_t(root)] >= 0) continue;
    std::vector<Frame> stack{{root, -1, 0}};
    disc[std::size_t(root)] = low[std::size_t(root)] = time++;
    while (!stack.empty()) {
      Frame& f = stack.back();
      const auto& nb = adj[std::size_t(f.v)];
      if (f.next < nb.size()) {
        const auto [u, e] = nb[f.next++];
        if (e == f.viaEdge) continue;
        if (disc[std::size_t(u)] < 0) {
          disc[std::size_t(u)] = low[std::size_t(u)] = time++;
          stack.push_back({u, e, 0});
        } else {
          low[std::size_t(f.v)] = std::min(low[std::size_t(f.v)], disc[std::size_t(u)]);
        }
      } else {
        const Frame done = f;
        stack.pop_back();
        if (!stack.empty()) {
          const int p = stack.back().v;
          low[std::size_t(p)] = std::min(low[std::size_t(p)], low[std::size_t(done.v)]);
          if (low[std::size_t(done.v)] > disc[std::size_t(p)]) bridge[std::size_t(done.viaEdge)] = 1;
        }
      }
    }
  }
  for (char& b : bridge) b = !b;
  return bridge;
}

std::vector<std::array<int, 2>> loopEdges(const Cage& cage) {
  const std::vector<std::array<int, 2>> edges = cageEdges(cage);
  if (cage.closed && cage.edges.empty()) return edges;
  const std::vector<char> onLoop = loopEdgeFlags(cage);
  std::vector<std::array<int, 2>> loops;
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (onLoop[e]) loops.push_back(edges[e]);
  return loops;
}

bool hasInterior(const Cage& cage) { return cage.closed || !loopEdges(cage).empty(); }

CageQueries::CageQueries(const Cage& cage)
    : m_C(cage.C), m_closed(cage.closed), m_edges(cageEdges(cage)), m_loops(loopEdges(cage)) {}

bool CageQueries::inside(const Vec2& x) const {
  bool inside = false;
  for (const auto& [a, b] : m_loops) {
    const Vec2 A = m_C.row(a), B = m_C.row(b);
    if ((A.y() > x.y()) != (B.y() > x.y())) {
      const double xc = A.x() + (x.y() - A.y()) * (B.x() - A.x()) / (B.y() - A.y());
      if (x.x() < xc) inside = !inside;
    }
  }
  return inside;
}

double CageQueries::distance(const Vec2& x) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : m_edges) best = std::min(best, pointSegmentDistance(x, m_C.row(a), m_C.row(b)));
  return best;
}

bool CageQueries::segmentCrosses(const Vec2& p, const Vec2& q) const {
  const Points& C = m_C;
  const Vec2 d = q - p;
  const double len = d.norm();
  if (len == 0.0) return false;
  // Parameters along p→q where the segment meets the cage; between consecutive ones the segment
  // is either on the cage or wholly inside or outside. It crosses when two such pieces disagree.
  std::vector<double> ts{0.0, 1.0};
  for (const auto& [a, b] : m_edges) {
    const Vec2 A = C.row(a), B = C.row(b), e = B - A;
    const double denom = cross(d, e);
    if (std::abs(denom) > 1e-14 * len * e.norm()) {
      const double t = cross(A - p, e) / denom, s = cross(A - p, d) / denom;
      if (s >= -1e-12 && s <= 1 + 1e-12 && t > 0.0 && t < 1.0) ts.push_back(t);
    } else if (std::abs(cross(A - p, d)) <= 1e-12 * len * std::max(len, (A - p).norm())) {
      for (const Vec2& V : {A, B}) {  // collinear: the overlap's ends split the segment
        const double t = (V - p).dot(d) / (len * len);
        if (t > 0.0 && t < 1.0) ts.push_back(t);
      }
    }
  }
  if (!m_closed) return ts.size() > 2;
  std::sort(ts.begin(), ts.end());
  int status = -1;  // -1 unknown, 0 outside, 1 inside
  for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
    if (ts[k + 1] - ts[k] <= 1e-12) continue;
    const Vec2 mid = p + 0.5 * (ts[k] + ts[k + 1]) * d;
    if (distance(mid) <= 1e-9 * len) continue;  // this piece runs along the cage
    const int in = inside(mid) ? 1 : 0;
    if (status >= 0 && in != status) return true;
    status = in;
  }
  return false;
}

bool insideCage(const Cage& cage, const Vec2& x) { return CageQueries(cage).inside(x); }

bool segmentCrossesCage(const Cage& cage, const Vec2& a, const Vec2& b) { return CageQueries(cage).segmentCrosses(a, b); }

Vec2 closestPointOnSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return a + t * d;
}

double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) { return (closestPointOnSegment(p, a, b) - p).norm(); }

double segmentSegmentDistance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = cross(b - a, c - a), o2 = cross(b - a, d - a), o3 = cross(d - c, a - c), o4 = cross(d - c, b - c);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return 0.0;
  return std::min({pointSegmentDistance(a, c, d), pointSegmentDistance(b, c, d), pointSegmentDistance(c, a, b),
                   pointSegmentDistance(d, a, b)});
}

double distanceToCage(const Cage& cage, const Vec2& x) { return CageQueries(cage).distance(x); }

std::vector<int> convexHull(const Points& C) {
  const int m = static_cast<int>(C.rows());
  std::vector<int> idx(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) idx[static_cast<std::size_t>(i)] = i;
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return C(a, 0) < C(b, 0) || (C(a, 0) == C(b, 0) && C(a, 1) < C(b, 1)); });
  if (m < 3) return idx;
  std::vector<int> hull(2 * static_cast<std::size_t>(m));
  int k = 0;
  auto turn = [&](int o, int a, int b) { return cross(Vec2(C.row(a)) - Vec2(C.row(o)), Vec2(C.row(b)) - Vec2(C.row(o))); };
  for (int i = 0; i < m; ++i) {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], idx[i]) <= 0) --k;
    hull[k++] = idx[i];
  }
  for (int i = m - 2, t = k + 1; i >= 0; --i) {
    while (k >= t && turn(hull[k - 2], hull[k - 1], idx[i]) <= 0) --k;
    hull[k++] = idx[i];
  }
  hull.resize(static_cast<std::size_t>(k - 1));
  return hull;
}

}  // namespace kc
