// Fixed samples: controls, edge samples at a common spacing, domain frame.
#include <gtest/gtest.h>

#include "kc/sampling/boundary.h"
#include "test_shapes.h"

namespace kc::sampling {
namespace {

TEST(Boundary, SquareEdgesSampledEvenlyWithoutRepeatingControls) {
  const Cage cage = test::cageFrom({{0, 0}, {100, 0}, {100, 100}, {0, 100}});
  const SampleSet S = boundarySamples(cage, 10.0);
  ASSERT_EQ(S.size(), 4 + 4 * 9);
  EXPECT_NO_THROW(S.validate(4));
  EXPECT_EQ(S.X.topRows(4), cage.C);
  for (Index i = 4; i < S.size(); ++i) {
    const int a = S.edge(i, 0), b = S.edge(i, 1);
    EXPECT_EQ(b, (a + 1) % 4);
    const Vec2 A = cage.C.row(a), B = cage.C.row(b), x = S.X.row(i);
    const double t = (x - A).dot(B - A) / (B - A).squaredNorm();
    EXPECT_NEAR(t * 10.0, std::round(t * 10.0), 1e-12) << "multiples of h along the edge";
    EXPECT_NEAR((A + t * (B - A) - x).norm(), 0.0, 1e-12);
  }
}

TEST(Boundary, EdgePiecesRoundToNearestSpacing) {
  EXPECT_EQ(edgePieces(3.0, 10.0), 1);
  EXPECT_EQ(edgePieces(14.0, 10.0), 1);
  EXPECT_EQ(edgePieces(16.0, 10.0), 2);
  EXPECT_EQ(edgePieces(100.0, 10.0), 10);
}

TEST(Boundary, OpenCageUsesItsEdgeList) {
  Cage stick;
  stick.C.resize(3, 2);
  stick.C << 0, 0, 50, 0, 50, 50;
  stick.closed = false;
  stick.edges = {{0, 1}, {1, 2}};
  EXPECT_EQ(cageEdges(stick).size(), 2u);
  const SampleSet S = boundarySamples(stick, 10.0);
  EXPECT_EQ(S.size(), 3 + 2 * 4);
  Cage implicitClosed;
  implicitClosed.C = stick.C;
  EXPECT_EQ(cageEdges(implicitClosed).size(), 3u);
}

TEST(Boundary, FramePointsLieOnTheRectangleWithCorners) {
  const Rect r{-12, -12, 212, 112};
  const Points F = framePoints(r, 8.0);
  EXPECT_EQ(F.rows(), 2 * (28 + 16));
  int corners = 0;
  for (Index i = 0; i < F.rows(); ++i) {
    EXPECT_TRUE(r.contains(F.row(i)));
    EXPECT_EQ(r.insideDistance(F.row(i)), 0.0);
    const bool cx = F(i, 0) == r.x0 || F(i, 0) == r.x1, cy = F(i, 1) == r.y0 || F(i, 1) == r.y1;
    corners += cx && cy;
  }
  EXPECT_EQ(corners, 4);
}

TEST(Boundary, DropNearCageKeepsOnlyDistantPoints) {
  const Cage cage = test::cageFrom({{0, 0}, {10, 0}, {10, 10}, {0, 10}});
  Points P(3, 2);
  P << 5, 5, 5, 0.5, 20, 20;
  const Points Q = dropNearCage(cage, P, 1.0);
  ASSERT_EQ(Q.rows(), 2);
  EXPECT_EQ(Q(0, 1), 5.0);
  EXPECT_EQ(Q(1, 0), 20.0);
}

}  // namespace
}  // namespace kc::sampling
