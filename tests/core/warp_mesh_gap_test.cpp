// The warp mesh at a narrow gap of the cage: no triangle of the inside spans the gap, so pulling
// one side cannot drag the picture of the other (WarpMeshOptions::followCage).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>

#include "kc/core/warp_mesh.h"
#include "warp_fixtures.h"

namespace kc {
namespace {

/// Two legs joined at the top, 3 px apart (the gap x ∈ [58.5, 61.5], y ∈ [40, 90]) in 120×100.
Cage legsCage() {
  Points C(8, 2);
  C << 20, 10, 100, 10, 100, 90, 61.5, 90, 61.5, 40, 58.5, 40, 58.5, 90, 20, 90;
  return Cage::polygon(C);
}

/// Triangles of the mesh's inside (all of them in Fixed/Transparent, those after the outside ones
/// in Pinned) with a point in the gap: its centroid or an edge's midpoint.
int insideTrianglesAcrossTheGap(const WarpMesh& mesh) {
  const CageQueries queries(mesh.cage());
  const Points& R = mesh.restVertices();
  int across = 0;
  for (std::size_t t = std::size_t(mesh.outsideTriangles()); t < mesh.triangles().size(); ++t) {
    const auto& T = mesh.triangles()[t];
    const Vec2 a = R.row(T[0]), b = R.row(T[1]), c = R.row(T[2]);
    bool out = false;
    for (const Vec2& p : {Vec2((a + b + c) / 3.0), Vec2((a + b) / 2.0), Vec2((b + c) / 2.0), Vec2((c + a) / 2.0)})
      out = out || (!queries.inside(p) && queries.distance(p) > 1e-9);
    across += out ? 1 : 0;
  }
  return across;
}

TEST(WarpMeshGap, NoInsideTriangleSpansAThreePixelGap) {
  const Cage cage = legsCage();
  for (OutsideMode mode : {OutsideMode::Pinned, OutsideMode::Fixed, OutsideMode::Transparent}) {
    for (double spacing : {4.0, 7.0}) {
      WarpMeshOptions o;
      o.outside = mode;
      o.spacing = spacing;
      const WarpMesh mesh(120, 100, cage, o);
      EXPECT_EQ(insideTrianglesAcrossTheGap(mesh), 0) << toString(mode) << " at " << spacing << " px";
    }
  }
  // The regular grid (followCage off) has triangles across the gap: what the test catches.
  WarpMeshOptions grid;
  grid.outside = OutsideMode::Fixed;
  grid.followCage = false;
  EXPECT_GT(insideTrianglesAcrossTheGap(WarpMesh(120, 100, cage, grid)), 0);
}

/// Pixels of the right leg next to the gap (x 62..66, y 45..85) that differ from the source
/// after the left leg's inner side moves 6 px left, in Fixed mode. Weights: the edge data at the
/// nearest cage point (each control pulls only the edges next to it, as local weights do across a
/// gap), so the right leg's own vertices stay put.
int rightLegPixelsChanged(bool followCage) {
  const Cage cage = legsCage();
  WarpMeshOptions o;
  o.outside = OutsideMode::Fixed;
  o.followCage = followCage;
  WarpMesh mesh(120, 100, cage, o);
  const Points& R = mesh.restVertices();
  Weights W(R.rows(), cage.size());
  for (Index v = 0; v < R.rows(); ++v) W.row(v) = edgeDataAt(cage, R.row(v)).transpose();
  mesh.setWeights(W);
  Pose pose = restPose(cage.size());
  pose[5].translate = Vec2(-6, 0);  // the left leg's inner corners at the top and bottom of the gap
  pose[6].translate = Vec2(-6, 0);
  mesh.deform(pose);
  Image src(120, 100);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 120; ++x) {
      std::uint8_t* p = src.pixel(x, y);
      p[0] = std::uint8_t(7 * x), p[1] = std::uint8_t(11 * y), p[2] = std::uint8_t(3 * (x + y)), p[3] = 255;
    }
  const Image out = mesh.render(src);
  int changed = 0;
  for (int y = 45; y <= 85; ++y)
    for (int x = 62; x <= 66; ++x)
      for (int c = 0; c < 4; ++c) changed += std::abs(int(out.pixel(x, y)[c]) - int(src.pixel(x, y)[c])) > 1 ? 1 : 0;
  return changed;
}

TEST(WarpMeshGap, PullingOneSideOfTheGapLeavesTheOtherSide) {
  EXPECT_EQ(rightLegPixelsChanged(true), 0);
  EXPECT_GT(rightLegPixelsChanged(false), 0) << "the regular grid drags the right leg along: what the test catches";
}

}  // namespace
}  // namespace kc
