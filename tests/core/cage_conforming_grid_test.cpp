// The cage-conforming warp mesh of the pinned mode (WarpMeshOptions::followCage): every triangle
// lies wholly inside or outside the cage and the triangles cover the image once. (The fold repair
// on it, which never moves a vertex inside or on the cage: exterior_untangle_test.cpp.)
#include <gtest/gtest.h>

#include "kc/core/cage_conforming_grid.h"
#include "kc/core/warp_mesh.h"
#include "warp_fixtures.h"

namespace kc {
namespace {

TEST(CageConformingGrid, TrianglesLieOnOneSideAndCoverTheImage) {
  const Cage cage = lCage();
  const std::vector<double> xs = gridAxis(120, 4.0), ys = gridAxis(100, 4.0);
  std::vector<std::uint8_t> exterior(xs.size() * ys.size());
  for (std::size_t j = 0; j < ys.size(); ++j)
    for (std::size_t i = 0; i < xs.size(); ++i) exterior[j * xs.size() + i] = insideCage(cage, Vec2(xs[i], ys[j])) ? 0 : 1;
  const CageConformingGrid g = cageConformingGrid(xs, ys, cage, exterior);
  ASSERT_GT(g.outsideTriangles, 0);
  ASSERT_LT(g.outsideTriangles, Index(g.T.size()));
  // Every cage point is a vertex.
  for (Index i = 0; i < cage.size(); ++i) {
    bool found = false;
    for (Index v = g.gridVertices; v < g.V.rows() && !found; ++v) found = (Vec2(g.V.row(v)) - Vec2(cage.C.row(i))).norm() < 1e-12;
    EXPECT_TRUE(found) << "cage point " << i;
  }
  double area = 0.0;
  for (std::size_t t = 0; t < g.T.size(); ++t) {
    const Vec2 a = g.V.row(g.T[t][0]), b = g.V.row(g.T[t][1]), c = g.V.row(g.T[t][2]);
    const double a2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    ASSERT_GT(a2, 0.0) << "counter-clockwise, not degenerate";
    area += 0.5 * a2;
    const bool inside = Index(t) >= g.outsideTriangles;
    // Points well inside the triangle are on its side of the cage (no triangle crosses it).
    for (const Vec2& w : {Vec2(1.0 / 3, 1.0 / 3), Vec2(0.8, 0.1), Vec2(0.1, 0.8), Vec2(0.1, 0.1)}) {
      const Vec2 p = a + w.x() * (b - a) + w.y() * (c - a);
      if (distanceToCage(cage, p) < 1e-9) continue;
      ASSERT_EQ(insideCage(cage, p), inside) << "triangle " << t;
    }
    for (int v : g.T[t]) ASSERT_FALSE(g.unused[std::size_t(v)]);
  }
  EXPECT_NEAR(area, (xs.back() - xs.front()) * (ys.back() - ys.front()), 1e-6) << "the image is covered once";
}

}  // namespace
}  // namespace kc
