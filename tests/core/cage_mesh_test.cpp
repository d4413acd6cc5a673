#include "kc/core/lbc/cage_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "lbc_cages.h"

namespace kc {
namespace {

double angleAt(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = b - a, v = c - a;
  return std::acos(std::clamp(u.dot(v) / (u.norm() * v.norm()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

TEST(CageMesh, ControlsFirstEdgePointsOnTheirEdgesAndAreaOfTheCage) {
  const Cage cage = test::starCage();
  CageMeshOptions options;
  options.spacing = 9.0;
  const CageMesh mesh = meshCageInterior(cage, options);
  ASSERT_EQ(mesh.status, SolveStatus::Ok);
  const Index m = cage.size();
  ASSERT_EQ(mesh.controls, m);
  EXPECT_GT(mesh.size(), 400);
  for (Index i = 0; i < m; ++i) EXPECT_EQ(mesh.V.row(i), cage.C.row(i)) << "control " << i;
  for (Index v = m; v < mesh.boundary; ++v) {
    const int k = mesh.edge(v, 0), l = mesh.edge(v, 1);
    ASSERT_EQ((k + 1) % m, l) << "vertex " << v << " is not on a cage edge";
    EXPECT_GT(mesh.t(v), 0.0);
    EXPECT_LT(mesh.t(v), 1.0);
    EXPECT_EQ(mesh.V.row(v), ((1.0 - mesh.t(v)) * cage.C.row(k) + mesh.t(v) * cage.C.row(l)).eval());
  }
  for (Index v = mesh.boundary; v < mesh.size(); ++v) {
    EXPECT_EQ(mesh.edge(v, 0), -1);
    EXPECT_TRUE(insideCage(cage, mesh.V.row(v))) << "interior vertex " << v << " outside the cage";
    EXPECT_GT(distanceToCage(cage, mesh.V.row(v)), 1e-6);
  }

  // The triangles tile the cage: areas sum to the polygon's, all oriented the same way; every
  // mesh edge with one triangle joins two cage vertices; edges ≤ h; angles ≥ the bound
  // (the star's smallest corner, 36°, is above it).
  double area = 0.0, longest = 0.0, smallest = 180.0;
  std::map<std::pair<int, int>, int> count;
  int sign = 0;
  for (const auto& t : mesh.T) {
    const Vec2 a = mesh.V.row(t[0]), b = mesh.V.row(t[1]), c = mesh.V.row(t[2]);
    const double twice = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    ASSERT_NE(twice, 0.0);
    if (sign == 0) sign = twice > 0 ? 1 : -1;
    EXPECT_EQ(sign, twice > 0 ? 1 : -1);
    area += 0.5 * std::abs(twice);
    for (int e = 0; e < 3; ++e) {
      const int p = t[std::size_t(e)], q = t[std::size_t((e + 1) % 3)];
      ++count[{std::min(p, q), std::max(p, q)}];
      longest = std::max(longest, (mesh.V.row(p) - mesh.V.row(q)).norm());
    }
    smallest = std::min({smallest, angleAt(a, b, c), angleAt(b, c, a), angleAt(c, a, b)});
  }
  EXPECT_NEAR(area, std::abs(signedArea(cage.C)), 1e-9 * area);
  EXPECT_LE(longest, options.spacing * (1 + 1e-9));
  EXPECT_GE(smallest, options.minAngleDegrees - 1e-6);
  int boundaryEdges = 0;
  for (const auto& [e, c] : count) {
    ASSERT_LE(c, 2);
    if (c == 1) {
      ++boundaryEdges;
      EXPECT_LT(e.first, mesh.boundary);
      EXPECT_LT(e.second, mesh.boundary);
    }
  }
  EXPECT_EQ(boundaryEdges, mesh.boundary);  // a closed polygon: as many edges as points
}

TEST(CageMesh, PointsTheMesherAddsOnTheCageAreRecorded) {
  // A thin spike forces the mesher to split constrained edges (encroachment) beyond the pre-split.
  Points C(5, 2);
  C << 0, 0, 100, 0, 100, 100, 52, 100, 50, 3;
  CageMeshOptions options;
  options.spacing = 40.0;
  const CageMesh mesh = meshCageInterior(Cage::polygon(C), options);
  ASSERT_EQ(mesh.status, SolveStatus::Ok);
  int added = 0;  // edge points that are not the pre-split ones (t ≠ p / ⌈length/h⌉)
  for (Index v = mesh.controls; v < mesh.boundary; ++v) {
    const int k = mesh.edge(v, 0), l = mesh.edge(v, 1);
    ASSERT_GE(k, 0);
    const Vec2 a = C.row(k), b = C.row(l);
    const double pieces = std::ceil((b - a).norm() / options.spacing - 1e-9);
    added += std::abs(mesh.t(v) * pieces - std::round(mesh.t(v) * pieces)) > 1e-9;
    EXPECT_LT(pointSegmentDistance(mesh.V.row(v), a, b), 1e-12);
    EXPECT_NEAR((Vec2(mesh.V.row(v)) - a).norm(), mesh.t(v) * (b - a).norm(), 1e-9);
  }
  EXPECT_GT(added, 0);
  for (Index v = mesh.boundary; v < mesh.size(); ++v) EXPECT_GT(distanceToCage(Cage::polygon(C), mesh.V.row(v)), 1e-9);
}

TEST(CageMesh, ASizingFieldGradesTheMeshAtTheNarrowPlaceOnly) {
  // A square with a slit 3 px wide cut in from below: featureSizing refines along the slit
  // (h = lfs / k = 1.5 px there at k = 2) and leaves h = 10 px away from it.
  const Cage cage = test::slitCage();
  const Points& C = cage.C;
  SizingOptions so;
  so.hMax = 10.0;
  so.featureSamples = so.outsideFeatureSamples = 2.0;
  so.outsideNarrowWidth = so.narrowWidth;
  auto sizing = std::make_shared<SizingField>(featureSizing(cage, {}, so));
  ASSERT_TRUE(sizing->graded());
  EXPECT_NEAR(sizing->hMin(), 1.5, 1e-9);
  CageMeshOptions options;
  options.spacing = so.hMax;
  const CageMesh uniform = meshCageInterior(cage, options);
  options.sizing = sizing;
  const CageMesh mesh = meshCageInterior(cage, options);
  ASSERT_EQ(mesh.status, SolveStatus::Ok);
  // Every triangle within the local spacing at its centroid, none thinner than the angle bound
  // (the slit's corners are right angles); finer than 10 px only near the slit.
  double worst = 0.0, smallest = 180.0, area = 0.0, finestAway = so.hMax;
  for (const auto& t : mesh.T) {
    const Vec2 a = mesh.V.row(t[0]), b = mesh.V.row(t[1]), c = mesh.V.row(t[2]), centroid = (a + b + c) / 3.0;
    const double longest = std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
    worst = std::max(worst, longest / std::min(so.hMax, (*sizing)(centroid)));
    smallest = std::min({smallest, angleAt(a, b, c), angleAt(b, c, a), angleAt(c, a, b)});
    area += 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    if (std::abs(centroid.x() - 150.0) > 60.0) finestAway = std::min(finestAway, longest);
  }
  EXPECT_LE(worst, 1.0 + 1e-9);
  EXPECT_GE(smallest, options.minAngleDegrees - 1e-6);
  EXPECT_NEAR(area, std::abs(signedArea(C)), 1e-9 * area);
  EXPECT_GT(finestAway, 0.25 * so.hMax);
  // Edge points on their edges at their parameters.
  for (Index v = mesh.controls; v < mesh.boundary; ++v) {
    const Vec2 a = C.row(mesh.edge(v, 0)), b = C.row(mesh.edge(v, 1));
    EXPECT_EQ(Vec2(mesh.V.row(v)), ((1.0 - mesh.t(v)) * a + mesh.t(v) * b).eval());
  }
  // More vertices than the uniform mesh, far fewer than a uniform mesh at the slit's spacing.
  EXPECT_GT(mesh.size(), uniform.size());
  EXPECT_LT(double(mesh.size()), 0.25 * estimateMeshVertices(cage, sizing->hMin()));
  // Null sizing is the uniform mesh.
  options.sizing = nullptr;
  const CageMesh again = meshCageInterior(cage, options);
  EXPECT_EQ(again.V, uniform.V);
  EXPECT_EQ(again.T, uniform.T);
}

TEST(CageMesh, EstimatedVertexCountsMatchTheMesh) {
  for (const Cage& cage : {test::starCage(), test::lCage()}) {
    CageMeshOptions options;
    options.spacing = spacingForVertexCount(cage, 2000);
    EXPECT_NEAR(estimateMeshVertices(cage, options.spacing), double(meshCageInterior(cage, options).size()), 0.15 * 2000);
  }
}

TEST(CageMesh, RefusesWhatItCannotMesh) {
  Cage open = test::starCage();
  open.closed = false;
  EXPECT_THROW(meshCageInterior(open), std::invalid_argument);
  CageMeshOptions options;
  options.spacing = 0.0;
  EXPECT_THROW(meshCageInterior(test::starCage(), options), std::invalid_argument);
  options.spacing = 0.5;
  options.maxVertices = 1000;
  const CageMesh mesh = meshCageInterior(test::starCage(), options);
  EXPECT_EQ(mesh.status, SolveStatus::TooLarge);
  EXPECT_EQ(mesh.size(), 0);
}

TEST(CageMesh, SpacingForVertexCountHitsTheTarget) {
  const Cage cage = test::starCage();
  for (Index target : {1000, 4000}) {
    CageMeshOptions options;
    options.spacing = spacingForVertexCount(cage, target);
    const Index got = meshCageInterior(cage, options).size();
    EXPECT_NEAR(double(got), double(target), 0.1 * double(target)) << target;
  }
}

}  // namespace
}  // namespace kc
