#include "kc/core/cage_edge_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include "random_point.h"

namespace kc {
namespace {

/// A random star-shaped polygon around (cx, cy): m points at increasing angles, radii in [r0, r1].
Cage randomStar(std::mt19937& rng, int m, double cx, double cy, double r0, double r1) {
  std::uniform_real_distribution<double> radius(r0, r1), jitter(-0.3, 0.3);
  Points C(m, 2);
  for (int i = 0; i < m; ++i) {
    const double t = 2.0 * M_PI * (i + 0.5 + jitter(rng)) / m, r = radius(rng);
    C.row(i) << cx + r * std::cos(t), cy + r * std::sin(t);
  }
  return Cage::polygon(C);
}

double bruteDistance(const Cage& cage, const Vec2& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : cageEdges(cage)) best = std::min(best, pointSegmentDistance(x, cage.C.row(a), cage.C.row(b)));
  return best;
}

double bruteSegmentDistance(const Cage& cage, const Vec2& p, const Vec2& q) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : cageEdges(cage))
    best = std::min(best, segmentSegmentDistance(p, q, cage.C.row(a), cage.C.row(b)));
  return best;
}

/// Every query of the grid equals the brute force over all edges (min(·, maxDistance)), for
/// points and segments inside, outside and far from the cage, with cells from tiny to huge;
/// `queries` random points and segments per cell size.
void expectMatchesBruteForce(const Cage& cage, std::mt19937& rng, int queries = 400) {
  std::uniform_real_distribution<double> coord(-300.0, 800.0), len(0.0, 60.0), ang(0.0, 2.0 * M_PI);
  std::uniform_real_distribution<double> reach(0.1, 80.0);
  for (double cell : {0.01, 3.0, 25.0, 5000.0}) {
    const CageEdgeGrid grid(cage, cell);
    for (int k = 0; k < queries; ++k) {
      const Vec2 x = test::randomPoint(coord, rng);
      const double t = ang(rng), r = reach(rng);
      const Vec2 y = x + len(rng) * Vec2(std::cos(t), std::sin(t));
      EXPECT_EQ(grid.distance(x, r), std::min(r, bruteDistance(cage, x))) << "cell " << cell;
      const double sd = bruteSegmentDistance(cage, x, y);
      EXPECT_EQ(grid.segmentDistance(x, y, r), std::min(r, sd)) << "cell " << cell;
      EXPECT_EQ(grid.segmentClear(x, y, r), sd >= r) << "cell " << cell;
    }
  }
}

/// Random star polygons of 5 to 205 vertices, `queries` queries per cell size on each.
void expectMatchesBruteForceOnRandomPolygons(int queries) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 6; ++trial) {
    const Cage cage = randomStar(rng, 5 + 40 * trial, 250.0, 250.0, 60.0, 240.0);
    expectMatchesBruteForce(cage, rng, queries);
  }
}

TEST(CageEdgeGrid, MatchesBruteForceOnRandomPolygons) { expectMatchesBruteForceOnRandomPolygons(100); }

TEST(CageEdgeGridSlow, MatchesBruteForceOnMoreQueries) { expectMatchesBruteForceOnRandomPolygons(400); }

TEST(CageEdgeGrid, UsesTheExplicitEdgesOfAnOpenCage) {
  // A stick figure's sticks: only the listed edges count (no closing edge 3 → 0).
  Cage cage;
  cage.C.resize(4, 2);
  cage.C << 0, 0, 100, 0, 100, 100, 0, 100;
  cage.closed = false;
  cage.edges = {{0, 1}, {1, 2}, {2, 3}};
  const CageEdgeGrid grid(cage, 10.0);
  EXPECT_DOUBLE_EQ(grid.distance(Vec2(5, 50), 1000.0), 50.0);  // edges 0 and 2 are 50 away, not 3 → 0 at 5
  EXPECT_TRUE(grid.segmentClear(Vec2(-10, 50), Vec2(10, 50), 5.0));  // would cross the missing 3 → 0
  EXPECT_FALSE(grid.segmentClear(Vec2(90, 50), Vec2(110, 50), 5.0));
  std::mt19937 rng(11);
  expectMatchesBruteForce(cage, rng);
}

TEST(CageEdgeGrid, ReportsEdgeIndicesOfTheOneEdgeList) {
  const Cage cage = Cage::polygon((Points(4, 2) << 0, 0, 10, 0, 10, 10, 0, 10).finished());
  const CageEdgeGrid grid(cage, 1.0);
  const auto edges = cageEdges(cage);
  std::vector<int> seen;
  grid.forEachEdgeNear(Vec2(9.5, 4), Vec2(11, 6), [&](int e, const Vec2& a, const Vec2& b) {
    EXPECT_EQ(a, Vec2(cage.C.row(edges[std::size_t(e)][0])));
    EXPECT_EQ(b, Vec2(cage.C.row(edges[std::size_t(e)][1])));
    seen.push_back(e);
  });
  EXPECT_NE(std::find(seen.begin(), seen.end(), 1), seen.end());  // edge 1 is (10,0)–(10,10)
}

}  // namespace
}  // namespace kc
