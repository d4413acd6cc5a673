#pragma once
/// The cage: control points and the edges between them (closed polygon or open polylines).

#include <array>
#include <string>
#include <vector>

#include "kc/core/types.h"

namespace kc {

struct Cage {
  Points C;                               ///< m×2 control points, in the user's order.
  std::vector<std::array<int, 2>> edges;  ///< Pairs of control indices.
  bool closed = true;                     ///< Closed polygon: edges are i → i+1 (mod m).

  Index size() const { return C.rows(); }
  /// A closed polygon through the points, edges i → i+1 (mod m).
  static Cage polygon(const Points& C);
};

/// Throws std::invalid_argument, with a message a user can act on, when the cage is unusable:
/// fewer than 3 points (closed) or 2 (open), non-finite coordinates, repeated points, an edge
/// index out of range or degenerate, all points collinear, or edges that intersect other than
/// at a shared end point. The user's point order is never changed. Expected O(m log m): points
/// through a grid, edge pairs only where edges share a grid cell of about the median edge length.
void validateCage(const Cage& cage);

/// The cage's edges, the one list every part of kcwarp uses: cage.edges when given (open
/// structures, edge graphs), else the closed polygon's i → i+1 (mod m).
std::vector<std::array<int, 2>> cageEdges(const Cage& cage);

/// The edges that lie on a closed loop of the edge graph (those that are not bridges, Tarjan's
/// O(V + E) search): the boundary of the cage's interior regions. A closed polygon: all edges; a
/// stick figure: its head's loop, not its sticks (open edges bound nothing). Order as cageEdges.
std::vector<std::array<int, 2>> loopEdges(const Cage& cage);
/// The same as one flag per edge of cageEdges(cage) (1: on a loop).
std::vector<char> loopEdgeFlags(const Cage& cage);

/// True when the cage is one closed polygon through its points in order: its edges are
/// i → i+1 (mod m), as Cage::polygon makes them (an edge graph that lists other edges is not).
bool isClosedPolygon(const Cage& cage);

/// True when the cage bounds an interior: a closed cage, or an edge graph with a closed loop
/// (a stick figure with a round head; thesis 6.2.2).
bool hasInterior(const Cage& cage);

/// The narrowest place of a cage: two control points joined by an edge (pointA, pointB), or two
/// edges that share no end point (edgeA, edgeB), closer than a distance. Unused indices are −1;
/// distance is +∞ when nothing is that close.
struct CageGap {
  double distance = 0.0;
  int pointA = -1, pointB = -1;
  int edgeA = -1, edgeB = -1;
};

/// The shortest edge or the closest pair of non-adjacent edges among those closer than `below`
/// (expected O(m log m), like validateCage).
CageGap narrowestGap(const Cage& cage, double below);

/// Signed area of the closed polygon C (positive = counter-clockwise in x-right/y-up axes).
double signedArea(const Points& C);

/// True when x lies inside the cage: even-odd rule over loopEdges (orientation does not matter),
/// so a stick crossing the ray does not count and open sticks have no inside. Points exactly on
/// an edge may go either way: callers treat edges separately.
bool insideCage(const Cage& cage, const Vec2& x);

/// True when the segment a–b properly crosses a cage edge: the two meet at a point that is
/// interior to both, or a–b passes through a cage vertex from one side of the cage to the other.
/// Touching at a or b (samples lying on the cage) is not a crossing.
bool segmentCrossesCage(const Cage& cage, const Vec2& a, const Vec2& b);

/// The cage's edges and loop edges found once, for many point and segment queries: insideCage,
/// distanceToCage and segmentCrossesCage find them again on every call (a graph search and
/// allocations, O(m) each). Each query is O(m). Holds a reference to the cage's points, which
/// must outlive it.
class CageQueries {
 public:
  explicit CageQueries(const Cage& cage);
  /// insideCage(cage, x).
  bool inside(const Vec2& x) const;
  /// distanceToCage(cage, x).
  double distance(const Vec2& x) const;
  /// segmentCrossesCage(cage, a, b).
  bool segmentCrosses(const Vec2& a, const Vec2& b) const;

 private:
  const Points& m_C;
  bool m_closed;
  std::vector<std::array<int, 2>> m_edges, m_loops;
};

/// The point of the segment a–b nearest to p (a when a = b).
Vec2 closestPointOnSegment(const Vec2& p, const Vec2& a, const Vec2& b);
/// Distance from p to the segment a–b.
double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b);
/// Distance between the segments a–b and c–d (0 when they properly cross).
double segmentSegmentDistance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d);

/// Distance from x to the nearest cage edge.
double distanceToCage(const Cage& cage, const Vec2& x);

/// Indices (into C) of the convex hull of the control points, counter-clockwise (y-up sense).
std::vector<int> convexHull(const Points& C);

}  // namespace kc
