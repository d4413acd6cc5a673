#include "kc/core/cage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace kc {
namespace {

Points pts(std::initializer_list<std::pair<double, double>> list) {
  Points P(static_cast<Index>(list.size()), 2);
  Index i = 0;
  for (auto [x, y] : list) P.row(i++) << x, y;
  return P;
}

std::string rejectReason(const Cage& cage) {
  try {
    validateCage(cage);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Cage, AcceptsSquareInEitherOrientation) {
  EXPECT_EQ(rejectReason(Cage::polygon(pts({{0, 0}, {10, 0}, {10, 10}, {0, 10}}))), "");
  EXPECT_EQ(rejectReason(Cage::polygon(pts({{0, 0}, {0, 10}, {10, 10}, {10, 0}}))), "");
}

TEST(Cage, RejectsDegenerateCagesWithReason) {
  EXPECT_NE(rejectReason(Cage::polygon(pts({{0, 0}, {1, 0}}))).find("at least 3"), std::string::npos);
  EXPECT_NE(rejectReason(Cage::polygon(pts({{0, 0}, {1, 1}, {2, 2}}))).find("collinear"), std::string::npos);
  EXPECT_NE(rejectReason(Cage::polygon(pts({{0, 0}, {1, 0}, {1, 1}, {0, 0}}))).find("repeated"), std::string::npos);
  // Bow tie: edges 0-1 and 2-3 cross.
  EXPECT_NE(rejectReason(Cage::polygon(pts({{0, 0}, {10, 10}, {10, 0}, {0, 10}}))).find("self-intersecting"),
            std::string::npos);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(rejectReason(Cage::polygon(pts({{0, 0}, {nan, 0}, {1, 1}}))).find("non-finite"), std::string::npos);
  // A spike folding back along its own edge.
  EXPECT_NE(rejectReason(Cage::polygon(pts({{0, 0}, {10, 0}, {5, 0}, {5, 5}}))), "");
}

TEST(Cage, InsideAndCrossing) {
  // U shape with a notch from above between x = 4 and x = 6.
  const Cage u = Cage::polygon(pts({{0, 0}, {10, 0}, {10, 10}, {6, 10}, {6, 2}, {4, 2}, {4, 10}, {0, 10}}));
  validateCage(u);
  EXPECT_TRUE(insideCage(u, Vec2(2, 5)));
  EXPECT_TRUE(insideCage(u, Vec2(8, 5)));
  EXPECT_FALSE(insideCage(u, Vec2(5, 5)));
  EXPECT_FALSE(insideCage(u, Vec2(-1, 5)));
  // Between the two arms: crosses the notch walls.
  EXPECT_TRUE(segmentCrossesCage(u, Vec2(2, 5), Vec2(8, 5)));
  // Below the notch: stays inside.
  EXPECT_FALSE(segmentCrossesCage(u, Vec2(2, 1), Vec2(8, 1)));
  // From a point on an edge into the inside: touches, does not cross.
  EXPECT_FALSE(segmentCrossesCage(u, Vec2(0, 5), Vec2(2, 5)));
  // Through the vertex (4,10) from outside-top to ... inside-left arm: crosses.
  EXPECT_TRUE(segmentCrossesCage(u, Vec2(5, 11), Vec2(3, 9)));
  EXPECT_NEAR(distanceToCage(u, Vec2(5, 5)), 1.0, 1e-12);
}

TEST(Cage, ConvexHullOfSquareWithInnerPoint) {
  const auto hull = convexHull(pts({{0, 0}, {10, 0}, {5, 3}, {10, 10}, {0, 10}}));
  EXPECT_EQ(hull.size(), 4u);
  for (int i : hull) EXPECT_NE(i, 2);
}

/// The O(m²) definition: do any two non-adjacent edges of the closed polygon meet?
bool selfIntersectsBruteForce(const Points& C) {
  const Index m = C.rows();
  for (Index e = 0; e < m; ++e)
    for (Index f = e + 1; f < m; ++f) {
      const Index e1 = (e + 1) % m, f1 = (f + 1) % m;
      if (e1 == f || f1 == e) continue;
      if (segmentSegmentDistance(C.row(e), C.row(e1), C.row(f), C.row(f1)) < 1e-9) return true;
    }
  return false;
}

// The grid-based validation finds exactly the self-intersections the quadratic definition finds,
// on random polygons of every density (most random polygons cross themselves, star-shaped ones
// sorted by angle do not).
TEST(Cage, GridValidationAgreesWithBruteForce) {
  std::uint64_t state = 12345;
  auto uniform = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 53);
  };
  int crossing = 0, simple = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int m = 3 + trial % 60;
    Points C(m, 2);
    const bool star = trial % 2 == 0;
    for (int i = 0; i < m; ++i) {
      if (star) {
        const double t = 2.0 * 3.141592653589793 * (i + 0.8 * uniform()) / m, r = 10.0 + 90.0 * uniform();
        C.row(i) << r * std::cos(t), r * std::sin(t);
      } else {
        C.row(i) << 100.0 * uniform(), 100.0 * uniform();
      }
    }
    const bool expected = selfIntersectsBruteForce(C);
    const std::string reason = rejectReason(Cage::polygon(C));
    EXPECT_EQ(!reason.empty(), expected) << "trial " << trial << ": " << reason;
    (expected ? crossing : simple)++;
  }
  EXPECT_GT(crossing, 50);
  EXPECT_GT(simple, 50);
}

TEST(Cage, NarrowestGapFindsShortEdgesAndSlivers) {
  // A pentagon whose edge 3–4 is 0.01 long.
  const Cage shortEdge = Cage::polygon(pts({{16, 16}, {80, 16}, {80, 80}, {16, 80}, {16, 79.99}}));
  CageGap g = narrowestGap(shortEdge, 3.0);
  EXPECT_NEAR(g.distance, 0.01, 1e-9);
  EXPECT_EQ(g.pointA, 3);
  EXPECT_EQ(g.pointB, 4);
  // A notch cut down to 0.5 above the bottom edge: edges 3, 4 and 5 come 0.5 close to edge 0.
  const Cage notch = Cage::polygon(pts({{0, 0}, {100, 0}, {100, 50}, {60, 50}, {60, 0.5}, {40, 0.5}, {40, 50}, {0, 50}}));
  g = narrowestGap(notch, 3.0);
  EXPECT_NEAR(g.distance, 0.5, 1e-9);
  EXPECT_EQ(g.edgeA, 0);
  EXPECT_TRUE(g.edgeB >= 3 && g.edgeB <= 5) << g.edgeB;
  EXPECT_TRUE(std::isinf(narrowestGap(notch, 0.4).distance));
  EXPECT_TRUE(std::isinf(narrowestGap(Cage::polygon(pts({{0, 0}, {10, 0}, {10, 10}, {0, 10}})), 3.0).distance));
}

/// A stick figure (thesis 6.2.2): a square "head" loop 0-1-2-3, a neck 2→4, arms 4→5, 4→6, a
/// torso 4→7, and a stick 1→8 off the head that crosses the head's middle row to its right.
Cage stickFigure() {
  Cage c;
  c.C = pts({{40, 0}, {60, 0}, {60, 20}, {40, 20}, {60, 40}, {20, 50}, {100, 50}, {60, 80}, {100, 15}});
  c.closed = false;
  c.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {2, 4}, {4, 5}, {4, 6}, {4, 7}, {1, 8}};
  return c;
}

TEST(Cage, LoopsOfAnEdgeGraphBoundItsInside) {
  const Cage c = stickFigure();
  ASSERT_NO_THROW(validateCage(c));
  const auto loops = loopEdges(c);
  EXPECT_EQ(loops, (std::vector<std::array<int, 2>>{{0, 1}, {1, 2}, {2, 3}, {3, 0}}));
  EXPECT_TRUE(hasInterior(c));
  EXPECT_TRUE(insideCage(c, Vec2(50, 10)));    // in the head
  EXPECT_FALSE(insideCage(c, Vec2(70, 10)));   // beside it: the stick 1→8 crosses the row to its right
  EXPECT_FALSE(insideCage(c, Vec2(60, 60)));   // between the sticks
  // Pure sticks (a tree) bound nothing; a polygon is all loop.
  Cage tree = c;
  tree.edges.erase(tree.edges.begin() + 3);  // open the head
  EXPECT_TRUE(loopEdges(tree).empty());
  EXPECT_FALSE(hasInterior(tree));
  EXPECT_FALSE(insideCage(tree, Vec2(50, 10)));
  const Cage square = Cage::polygon(pts({{0, 0}, {10, 0}, {10, 10}, {0, 10}}));
  EXPECT_EQ(loopEdges(square).size(), 4u);
  // Two loops joined by a stick (a bridge between them): both loops, not the stick.
  Cage twin;
  twin.C = pts({{0, 0}, {10, 0}, {10, 10}, {0, 10}, {30, 0}, {40, 0}, {40, 10}, {30, 10}});
  twin.closed = false;
  twin.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {1, 4}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
  EXPECT_EQ(loopEdges(twin).size(), 8u);
  EXPECT_TRUE(insideCage(twin, Vec2(35, 5)));
  EXPECT_FALSE(insideCage(twin, Vec2(20, 5)));
}

TEST(Cage, StickGraphsWithBadEdgesAreRefused) {
  Cage c = stickFigure();
  c.edges.push_back({8, 1});  // the stick 1→8 again
  EXPECT_NE(rejectReason(c).find("same edge"), std::string::npos) << rejectReason(c);
  c = stickFigure();
  c.edges.push_back({5, 6});  // hand to hand: crosses the torso 4→7 at (60, 50)
  EXPECT_NE(rejectReason(c).find("crosses"), std::string::npos) << rejectReason(c);
  c = stickFigure();
  c.edges.push_back({4, 9});  // no point 9
  EXPECT_NE(rejectReason(c).find("does not exist"), std::string::npos) << rejectReason(c);
}

}  // namespace
}  // namespace kc
