#include "kc/core/cage.h"

#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
}  // namespace kc
