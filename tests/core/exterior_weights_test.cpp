// The pinned outside mode's exterior weights (exterior_weights.h): harmonic extension of the
// cage's edge data to the image border, with a fixed anchor.
#include "kc/core/exterior_weights.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kc/core/parallel.h"
#include "kc/core/warp_mesh.h"
#include "warp_fixtures.h"

namespace kc {
namespace {

Cage rectangle(double x0, double y0, double x1, double y1) {
  Points C(4, 2);
  C << x0, y0, x1, y0, x1, y1, x0, y1;
  return Cage::polygon(C);
}

ExteriorWeights solve(int w, int h, double spacing, const Cage& cage) {
  return pinnedExteriorWeights(gridAxis(w, spacing), gridAxis(h, spacing), cage);
}

/// λ_i at the cage point closest to p (the piecewise-linear edge data), #m.
Eigen::VectorXd edgeDataAt(const Cage& cage, const Vec2& p) {
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(cage.size());
  double best = 1e300;
  for (const auto& [a, b] : cageEdges(cage)) {
    const Vec2 A = cage.C.row(a), d = Vec2(cage.C.row(b)) - A;
    const double s = std::clamp((p - A).dot(d) / d.squaredNorm(), 0.0, 1.0);
    if (const double dist = (A + s * d - p).norm(); dist < best) {
      best = dist;
      lambda.setZero();
      lambda(a) = 1 - s;
      lambda(b) = s;
    }
  }
  return lambda;
}

/// Checks the properties every exterior solution must have; returns the dense H (#V×(m+1)).
Weights checkProperties(const ExteriorWeights& E, Index m, int nx, int ny) {
  const auto& r = E.report;
  EXPECT_TRUE(r.ok);
  EXPECT_GE(r.minWeight, -1e-12);
  EXPECT_LE(r.maxWeight, 1.0 + 1e-12);
  EXPECT_LE(r.maxSum, 1.0 + 1e-12);
  EXPECT_EQ(E.H.rows(), Index(nx) * ny);
  EXPECT_EQ(E.H.cols(), m + 1);
  EXPECT_EQ(r.unknowns + r.anchored + r.following + r.interior, Index(nx) * ny);
  const Weights H = Weights(E.H);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Index v = Index(j) * nx + i;
      if (!E.exterior[std::size_t(v)]) {
        EXPECT_EQ(H.row(v).cwiseAbs().sum(), 0.0) << "interior rows are the field's";
        continue;
      }
      EXPECT_NEAR(H.row(v).sum(), 1.0, 1e-12) << "vertex " << v;
      EXPECT_GE(H.row(v).minCoeff(), -1e-12);
      EXPECT_LE(H.row(v).maxCoeff(), 1.0 + 1e-12);
      if (i == 0 || j == 0 || i == nx - 1 || j == ny - 1) {  // pinned, or following a cage that is near
        EXPECT_TRUE(H(v, m) == 1.0 || (H(v, m) == 0.0 && r.following > 0)) << "border vertex " << v;
      }
    }
  return H;
}

TEST(ExteriorWeights, BoundedPartitionOfUnityWithThePinnedBorder) {
  const Cage cage = lCage();
  const ExteriorWeights E = solve(120, 100, 4.0, cage);
  EXPECT_GT(E.report.unknowns, 300);
  EXPECT_GT(E.report.cutEdges, 40);
  EXPECT_EQ(E.report.fallbackEdges, 0);
  checkProperties(E, 8, 31, 26);
  // Even-odd classification agrees with insideCage at every vertex.
  const auto xs = gridAxis(120, 4.0), ys = gridAxis(100, 4.0);
  for (std::size_t j = 0; j < ys.size(); ++j)
    for (std::size_t i = 0; i < xs.size(); ++i)
      EXPECT_EQ(E.exterior[j * xs.size() + i] == 0, insideCage(cage, Vec2(xs[i], ys[j])));
}

TEST(ExteriorWeights, NextToTheCageTheWeightsAreTheEdgeData) {
  // Exterior vertices within a tenth of a cell of the cage take (almost) the cage's data there.
  const Cage cage = lCage();
  const double h = 1.0;
  const auto xs = gridAxis(120, h), ys = gridAxis(100, h);
  const ExteriorWeights E = pinnedExteriorWeights(xs, ys, cage);
  const Weights H = Weights(E.H);
  int checked = 0;
  for (std::size_t j = 1; j + 1 < ys.size(); ++j)
    for (std::size_t i = 1; i + 1 < xs.size(); ++i) {
      const Vec2 p(xs[i], ys[j]);
      const std::size_t v = j * xs.size() + i;
      if (!E.exterior[v] || distanceToCage(cage, p) > 0.1 * h) continue;
      ++checked;
      EXPECT_LT((H.row(Index(v)).head(8).transpose() - edgeDataAt(cage, p)).cwiseAbs().maxCoeff(), 0.03) << p.transpose();
    }
  EXPECT_GT(checked, 5);
}

TEST(ExteriorWeights, ConvergesUnderGridRefinement) {
  // Nested grids (120 = 30·4 = 60·2 = 120·1 cells): the solution at the coarse vertices approaches
  // the finest one (a self-convergence study; no closed form exists for this domain).
  const Cage cage = lCage();
  const Weights H1 = Weights(solve(120, 100, 1.0, cage).H);
  double err[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const int step = k == 0 ? 4 : 2;
    const ExteriorWeights E = solve(120, 100, double(step), cage);
    const Weights H = Weights(E.H);
    const int nx = 120 / step + 1, ny = 100 / step + 1;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Index v = Index(j) * nx + i, f = Index(j * step) * 121 + i * step;
        if (!E.exterior[std::size_t(v)] || H1.row(f).sum() == 0.0) continue;
        err[k] = std::max(err[k], (H.row(v) - H1.row(f)).cwiseAbs().maxCoeff());
      }
  }
  std::printf("max |h - h(spacing 1)|: spacing 4 %.4f, spacing 2 %.4f\n", err[0], err[1]);
  EXPECT_LT(err[0], 0.15);
  EXPECT_LT(err[1], 0.7 * err[0]) << "spacing 4: " << err[0] << ", spacing 2: " << err[1];
}

TEST(ExteriorWeights, AThinCageSeparatesItsTwoSides) {
  // A bar 1 px tall (a quarter of a grid cell): vertices above it follow its top edge, below it
  // its bottom edge, although grid edges jump over the bar.
  const Cage cage = rectangle(30.3, 50.2, 90.7, 51.2);
  const auto xs = gridAxis(120, 4.0), ys = gridAxis(100, 4.0);
  const ExteriorWeights E = pinnedExteriorWeights(xs, ys, cage);
  const Weights H = checkProperties(E, 4, int(xs.size()), int(ys.size()));
  EXPECT_EQ(E.report.interior, 0) << "no vertex inside a bar thinner than a cell";
  const std::size_t i = 15;  // x = 59.5, the bar's middle
  std::size_t above = 0;
  while (ys[above + 1] < 50.2) ++above;
  const Index a = Index(above * xs.size() + i), b = Index((above + 1) * xs.size() + i);
  EXPECT_GT(H(a, 0) + H(a, 1), 0.5);  // top edge: controls 0, 1
  EXPECT_LT(H(a, 2) + H(a, 3), 0.05);
  EXPECT_GT(H(b, 2) + H(b, 3), 0.5);  // bottom edge: controls 2, 3
  EXPECT_LT(H(b, 0) + H(b, 1), 0.05);
}

TEST(ExteriorWeights, OpenSticksHaveNoInterior) {
  Cage stick;
  stick.C.resize(3, 2);
  stick.C << 20, 30, 60, 50, 100, 40;
  stick.closed = false;
  stick.edges = {{0, 1}, {1, 2}};
  validateCage(stick);
  const auto xs = gridAxis(120, 4.0), ys = gridAxis(100, 4.0);
  const ExteriorWeights E = pinnedExteriorWeights(xs, ys, stick);
  const Weights H = checkProperties(E, 3, int(xs.size()), int(ys.size()));
  EXPECT_EQ(E.report.interior, 0);
  // Just above and just below the middle control, its weight dominates.
  for (const double y : {46.5, 54.5}) {
    std::size_t i = 0, j = 0;
    while (xs[i] < 59.0) ++i;
    while (ys[j] < y) ++j;
    EXPECT_GT(H(Index(j * xs.size() + i), 1), 0.4) << "y " << y;
  }
}

TEST(ExteriorWeights, HolesInsideLoopsCarryNoAnchor) {
  // Two loops, one inside the other: the ring between them is inside (even-odd), the hole is
  // outside but does not reach the border, so its weights sum to 1 (anchor ≈ 0).
  Cage cage;
  cage.C.resize(8, 2);
  cage.C << 20, 20, 100, 20, 100, 80, 20, 80, 45, 40, 75, 40, 75, 60, 45, 60;
  cage.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
  validateCage(cage);
  const auto xs = gridAxis(120, 2.0), ys = gridAxis(100, 2.0);
  const ExteriorWeights E = pinnedExteriorWeights(xs, ys, cage);
  const Weights H = checkProperties(E, 8, int(xs.size()), int(ys.size()));
  int hole = 0;
  for (std::size_t j = 0; j < ys.size(); ++j)
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const Vec2 p(xs[i], ys[j]);
      if (p.x() > 46 && p.x() < 74 && p.y() > 41 && p.y() < 59) {
        ++hole;
        const Index v = Index(j * xs.size() + i);
        ASSERT_TRUE(E.exterior[std::size_t(v)]);
        EXPECT_LE(H(v, 8), 8 * 1e-3 / 8 + 1e-9);  // at most the dropped entries
        EXPECT_LT(H.row(v).head(4).sum(), 1e-9) << "the outer loop's controls do not reach the hole";
      }
    }
  EXPECT_GT(hole, 50);
}

TEST(ExteriorWeights, CageCrossingTheImageBorder) {
  // Part of the cage lies beyond the left border: border vertices inside it belong to the field,
  // the others stay pinned.
  const Cage cage = rectangle(-30, 20, 50, 70);
  const auto xs = gridAxis(120, 4.0), ys = gridAxis(100, 4.0);
  const ExteriorWeights E = pinnedExteriorWeights(xs, ys, cage);
  const Weights H = checkProperties(E, 4, int(xs.size()), int(ys.size()));
  EXPECT_FALSE(E.exterior[std::size_t(12 * xs.size())]);  // (−0.5, 47.5): inside the cage
  EXPECT_TRUE(E.exterior[0]);
  EXPECT_EQ(H(0, 4), 1.0);  // the corner, 20 px from the cage, stays
  // (−0.5, 19.5) is 0.5 px from the cage's top edge where it leaves the picture: it follows the cage.
  EXPECT_GT(E.report.following, 0);
  const Index near = Index(5 * xs.size());
  ASSERT_NEAR(ys[5], 19.5, 1e-12);
  EXPECT_EQ(H(near, 4), 0.0);
  EXPECT_NEAR(H(near, 0) + H(near, 1), 1.0, 1e-12);
}

TEST(ExteriorWeights, IdenticalForOneAndTwoThreads) {
  const Cage cage = lCage();
  ExteriorWeights a, b;
  {
    ScopedThreadCount t(1);
    a = solve(120, 100, 3.0, cage);
  }
  {
    ScopedThreadCount t(2);
    b = solve(120, 100, 3.0, cage);
  }
  EXPECT_EQ(a.exterior, b.exterior);
  EXPECT_EQ(Weights(a.H), Weights(b.H));
}

}  // namespace
}  // namespace kc
