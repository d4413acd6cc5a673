// The drag area of Diagnostics (the pixels that move ≥ 0.5 px under a 40 px drag of one control),
// checked against a count made point by point.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "kc/app/diagnostics.h"
#include "kc/app/pipeline.h"

namespace kc::app {
namespace {

/// Even-odd point-in-polygon test, written here apart from the cage code the diagnostics use.
bool insidePolygon(const Points& C, double x, double y) {
  bool in = false;
  for (Index i = 0, j = C.rows() - 1; i < C.rows(); j = i++) {
    const double xi = C(i, 0), yi = C(i, 1), xj = C(j, 0), yj = C(j, 1);
    if ((yi > y) != (yj > y) && x < xi + (y - yi) * (xj - xi) / (yj - yi)) in = !in;
  }
  return in;
}

TEST(DragArea, MatchesAPointByPointCount) {
  // An L-shaped cage (non-convex: its weights are far from uniform) on a 64×56 picture.
  Points C(6, 2);
  C << 6, 6, 58, 6, 58, 24, 27, 24, 27, 50, 6, 50;
  BindParams p;
  p.spacing = 4.0;
  const Session s = bind(Cage::polygon(C), 64, 56, p);
  const Diagnostics d = diagnose(s, 64 * 56);  // the grid every pixel: the drag area every 2nd
  ASSERT_EQ(d.pixelStep, 1);
  ASSERT_EQ(d.drag.step, 2);

  // The count: every pixel centre (x + 0.5, y + 0.5), x and y even, inside the cage, evaluated alone.
  const Index m = C.rows();
  std::vector<Index> moved(static_cast<std::size_t>(m), 0);
  Index points = 0;
  double deepest = 1.0;
  for (int y = 0; y < 56; y += 2)
    for (int x = 0; x < 64; x += 2) {
      if (!insidePolygon(C, x + 0.5, y + 0.5)) continue;
      ++points;
      Points P(1, 2);
      P << x + 0.5, y + 0.5;
      const Weights w = s.field->weightsAt(P);
      for (Index i = 0; i < m; ++i) {
        if (w(0, i) >= 0.5 / 40.0) ++moved[static_cast<std::size_t>(i)];
        deepest = std::min(deepest, w(0, i));
      }
    }
  ASSERT_GT(points, 100);
  EXPECT_EQ(d.drag.points, points);
  double mean = 0.0, largest = 0.0;
  for (Index i = 0; i < m; ++i) {
    const double f = static_cast<double>(moved[static_cast<std::size_t>(i)]) / static_cast<double>(points);
    EXPECT_NEAR(d.drag.fraction[static_cast<std::size_t>(i)], f, 1e-12) << "control " << i;
    mean += f / static_cast<double>(m);
    largest = std::max(largest, f);
  }
  EXPECT_NEAR(d.drag.mean, mean, 1e-12);
  EXPECT_NEAR(d.drag.max, largest, 1e-12);
  EXPECT_NEAR(d.drag.fraction[static_cast<std::size_t>(d.drag.maxControl)], largest, 1e-12);
  EXPECT_NEAR(d.drag.minWeight, deepest, 1e-12);
  // Every control moves something, none the whole cage (the weights are not constant).
  EXPECT_GT(*std::min_element(d.drag.fraction.begin(), d.drag.fraction.end()), 0.0);
  EXPECT_LT(d.drag.max, 1.0);
}

TEST(DragArea, CountsThresholdAndReportsEmptyGrids) {
  // Rows: two points, three controls; the threshold 0.0125 counts (≥).
  Weights W(2, 3);
  W << 0.0125, 0.9875 - 0.02, 0.02,
       0.0124, 0.9976, -0.01;
  const DragArea a = dragArea(W, 2);
  EXPECT_DOUBLE_EQ(a.fraction[0], 0.5);
  EXPECT_DOUBLE_EQ(a.fraction[1], 1.0);
  EXPECT_DOUBLE_EQ(a.fraction[2], 0.5);
  EXPECT_DOUBLE_EQ(a.mean, 2.0 / 3.0);
  EXPECT_EQ(a.maxControl, 1);
  EXPECT_DOUBLE_EQ(a.minWeight, -0.01);
  const DragArea none = dragArea(Weights(0, 3), 2);
  EXPECT_EQ(none.points, 0);
  EXPECT_EQ(none.maxControl, -1);
}

}  // namespace
}  // namespace kc::app
