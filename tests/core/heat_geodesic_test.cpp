#include "kc/core/lbc/heat_geodesic.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kc/core/lbc/cage_mesh.h"
#include "lbc_cages.h"

namespace kc {
namespace {

/// Heat-method distances from the controls of `cage` meshed at spacing h.
struct Distances {
  CageMesh mesh;
  Eigen::MatrixXd D;
};

Distances distances(const Cage& cage, double h) {
  Distances r;
  CageMeshOptions options;
  options.spacing = h;
  r.mesh = meshCageInterior(cage, options);
  const TriangleGradients g = triangleGradients(r.mesh.V, r.mesh.T);
  std::vector<Index> sources;
  for (Index i = 0; i < cage.size(); ++i) sources.push_back(i);
  HeatGeodesicReport report;
  r.D = heatGeodesics(r.mesh.V, r.mesh.T, g, stiffnessMatrix(r.mesh.T, g, r.mesh.size()), sources, &report);
  EXPECT_TRUE(report.ok);
  return r;
}

TEST(HeatGeodesic, EuclideanInAConvexDomain) {
  Points C(4, 2);
  C << 0, 0, 200, 0, 200, 100, 0, 100;
  const Distances r = distances(Cage::polygon(C), 5.0);
  for (Index i = 0; i < 4; ++i) {
    double worst = 0.0;
    for (Index v = 0; v < r.mesh.size(); ++v)
      worst = std::max(worst, std::abs(r.D(v, i) - (r.mesh.V.row(v) - C.row(i)).norm()));
    EXPECT_LT(worst, 0.03 * 223.6) << "control " << i;  // ≤ 3% of the diameter (heat method, h = 5)
    EXPECT_EQ(r.D(i, i), 0.0);
  }
}

TEST(HeatGeodesic, GoesAroundTheReflexCorner) {
  // L-shape: from control 2 = (200, 100) to control 4 = (100, 200) the straight segment leaves
  // the domain; the geodesic bends at the reflex corner (100, 100): 100 + 100 = 200, not 141.
  const Distances r = distances(test::lCage(), 4.0);
  EXPECT_NEAR(r.D(4, 2), 200.0, 6.0);
  EXPECT_NEAR(r.D(2, 4), 200.0, 6.0);
  EXPECT_NEAR(r.D(0, 2), std::hypot(200.0, 100.0), 6.0);  // visible: straight
}

}  // namespace
}  // namespace kc
