// The warp mesh in the pinned outside mode: the image border stays, the inside follows the
// field, the background between stretches without folding.
#include <gtest/gtest.h>

#include <cmath>

#include "kc/core/deform.h"
#include "kc/core/warp_mesh.h"
#include "warp_fixtures.h"

namespace kc {
namespace {

WarpMesh meshWithMeanValue(const Cage& cage, OutsideMode mode, double spacing = 4.0, bool repairFolds = true,
                           double fadeBand = WarpMeshOptions{}.fadeBand) {
  WarpMeshOptions o;
  o.outside = mode;
  o.spacing = spacing;
  o.repairFolds = repairFolds;
  o.fadeBand = fadeBand;
  WarpMesh mesh(120, 100, cage, o);
  mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
  return mesh;
}

/// A pose that raises the L's right arm and turns it a little. The arm's corner (control 3) is
/// 14 px from the right border: a harmonic extension concentrates stretch at a convex cage corner
/// (its gradient grows like r^(-1/3) in the 270° exterior angle), so moving that corner by more
/// than about its distance to the pinned border folds a few pixels next to it (seen at a 13 px
/// move with a 0.2 rad turn); this pose stays below that.
Pose armPose() {
  Pose pose = restPose(8);
  pose[3] = {Vec2(3, -8), 0.1};
  pose[4] = {Vec2(4, -10), 0.1};
  return pose;
}

/// Displacement of the deformed mesh at rest point q (linear on the grid's triangles a-b-d, a-d-c).
Vec2 displacementAt(const WarpMesh& mesh, const Vec2& q) {
  const auto xs = gridAxis(mesh.width(), mesh.options().spacing), ys = gridAxis(mesh.height(), mesh.options().spacing);
  const int nx = int(xs.size());
  const double dx = xs[1] - xs[0], dy = ys[1] - ys[0];
  const int i = std::clamp(int((q.x() - xs[0]) / dx), 0, nx - 2), j = std::clamp(int((q.y() - ys[0]) / dy), 0, int(ys.size()) - 2);
  const double u = (q.x() - xs[std::size_t(i)]) / dx, v = (q.y() - ys[std::size_t(j)]) / dy;
  const Points& F = mesh.deformedVertices();
  const auto at = [&](int di, int dj) { return Vec2(F.row((j + dj) * nx + i + di)); };
  const Vec2 f = v <= u ? at(0, 0) + u * (at(1, 0) - at(0, 0)) + v * (at(1, 1) - at(1, 0))
                        : at(0, 0) + u * (at(1, 1) - at(0, 1)) + v * (at(0, 1) - at(0, 0));
  return f - q;
}

TEST(PinnedOutside, CornersStayAndTheInsideFollowsTheField) {
  const Cage cage = lCage();
  WarpMesh pinned = meshWithMeanValue(cage, OutsideMode::Pinned), field = meshWithMeanValue(cage, OutsideMode::Deform);
  const DeformReport rep = pinned.deform(armPose());
  field.deform(armPose());
  EXPECT_EQ(rep.flippedTriangles, 0);
  const Points& R = pinned.restVertices();
  const Points& F = pinned.deformedVertices();
  // The field's own deformation at the pinned mesh's vertices (its mesh follows the cage).
  const Points fieldAtR = deformPoints(meanValueWeights(cage.C, R), R, cage.C, armPose());
  double insideGap = 0.0, borderMove = 0.0, cornerMove = 0.0;
  for (Index v = 0; v < R.rows(); ++v) {
    const Vec2 x = R.row(v);
    if (!pinned.exteriorWeights()->exterior[std::size_t(v)])
      insideGap = std::max(insideGap, (F.row(v) - fieldAtR.row(v)).norm());
    if (x.x() < 0 || x.y() < 0 || x.x() > 119 || x.y() > 99) borderMove = std::max(borderMove, (F.row(v) - R.row(v)).norm());
    if ((x.x() < 0 || x.x() > 119) && (x.y() < 0 || x.y() > 99)) cornerMove = std::max(cornerMove, (F.row(v) - R.row(v)).norm());
  }
  EXPECT_EQ(cornerMove, 0.0) << "the image corners do not move";
  // The arm's corner moves ~10 px at 14 px from the border: the fade (which steepens the squeeze
  // there) leaves two slivers folded, and the fold repair lets four border vertices slide along
  // the border (by 0.74 px); without the fade the border stays exactly.
  EXPECT_LT(borderMove, 1.0) << "the image border slides at most a little";
  WarpMesh harmonic = meshWithMeanValue(cage, OutsideMode::Pinned, 4.0, true, 0.0);
  harmonic.deform(armPose());
  double harmonicBorder = 0.0;
  for (Index v = 0; v < R.rows(); ++v) {
    const Vec2 x = harmonic.restVertices().row(v);
    if (x.x() < 0 || x.y() < 0 || x.x() > 119 || x.y() > 99)
      harmonicBorder = std::max(harmonicBorder, (harmonic.deformedVertices().row(v) - harmonic.restVertices().row(v)).norm());
  }
  EXPECT_EQ(harmonicBorder, 0.0) << "without the fade the image border does not move";
  // (up to the compact weights' dropped entries, |w| ≤ 1e-3/m, which the field's own formula keeps)
  EXPECT_LT(insideGap, 0.01) << "inside the cage the field's weights are used unchanged";
  // The thesis mode moves the far corner; pinned does not.
  const Index corner = field.restVertices().rows() - 1;
  EXPECT_GT((field.deformedVertices().row(corner) - field.restVertices().row(corner)).norm(), 0.5);
}

TEST(PinnedOutside, TranslatingAllControlsTranslatesTheInsideAndKeepsTheBorder) {
  const Cage cage = lCage();
  const Vec2 d(6, -4);  // the cage stays clear of the pinned border (≥ 4 px)
  Pose pose = restPose(8);
  for (auto& p : pose) p.translate = d;
  // The default (with the fold repair) folds nothing; the harmonic extension alone folds slivers
  // next to the cage's top edge, which moves towards the border, and is checked below.
  EXPECT_EQ(meshWithMeanValue(cage, OutsideMode::Pinned).deform(pose).flippedTriangles, 0);
  // (the harmonic extension's own motion: without the fade, which scales it by φ(r / B))
  WarpMesh mesh = meshWithMeanValue(cage, OutsideMode::Pinned, 4.0, false, 0.0);
  mesh.deform(pose);
  const ExteriorWeights& E = *mesh.exteriorWeights();
  for (Index v = 0; v < mesh.restVertices().rows(); ++v) {
    const Vec2 u = mesh.deformedVertices().row(v) - mesh.restVertices().row(v);
    if (!E.exterior[std::size_t(v)]) {
      ASSERT_LT((u - d).norm(), 1e-9) << "inside: rigid translation";
      continue;
    }
    // Outside: u = (1 − anchor)·d, along d and no longer than it.
    ASSERT_LT(std::abs(u.x() * d.y() - u.y() * d.x()), 1e-9 * d.squaredNorm());
    ASSERT_LE(u.norm(), d.norm() + 1e-9);
    ASSERT_GE(u.dot(d), -1e-9);
    const double anchor = E.H.coeff(v, 8);
    ASSERT_NEAR(u.norm(), (1.0 - anchor) * d.norm(), 1e-9);
  }
}

TEST(PinnedOutside, ContinuousAcrossTheCage) {
  // Just inside and just outside the cage (δ = 1 px along the normal) the displacement differs by
  // no more than across the thesis mode's smooth field plus the exterior's own stretching over 2δ:
  // the exterior takes the cage's edge data, which the field reproduces on the edges.
  const Cage cage = lCage();
  WarpMesh pinned = meshWithMeanValue(cage, OutsideMode::Pinned, 2.0), field = meshWithMeanValue(cage, OutsideMode::Deform, 2.0);
  pinned.deform(armPose());
  field.deform(armPose());
  const double delta = 1.0;
  double jumpPinned = 0.0, jumpField = 0.0;
  const auto edges = cageEdges(cage);
  for (const auto& [a, b] : edges) {
    const Vec2 A = cage.C.row(a), B = cage.C.row(b);
    const Vec2 t = (B - A).normalized(), n(-t.y(), t.x());
    for (double s = 0.1; s < 0.95; s += 0.1) {
      const Vec2 p = A + s * (B - A);
      Vec2 in = p + delta * n, out = p - delta * n;
      if (!insideCage(cage, in)) std::swap(in, out);
      jumpPinned = std::max(jumpPinned, (displacementAt(pinned, in) - displacementAt(pinned, out)).norm());
      jumpField = std::max(jumpField, (displacementAt(field, in) - displacementAt(field, out)).norm());
    }
  }
  std::printf("displacement jump across the cage (2 px apart): pinned %.3f px, field everywhere %.3f px\n", jumpPinned,
              jumpField);
  EXPECT_LT(jumpPinned, 2.0 * jumpField + 1.0);
  EXPECT_LT(jumpPinned, 4.0);  // 2δ times the largest stretch the arm pose asks for (~2)
}

TEST(PinnedOutside, AStickFiguresLimbsMoveWithTheFieldAndTheBorderStays) {
  // A stick figure with a round head: the limbs are open sticks. Their bands move exactly as the
  // field moves them (as in the Deform mode), so a raised arm carries its paint; the corners stay.
  Cage figure;
  figure.C.resize(9, 2);
  figure.C << 60, 10, 70, 20, 60, 30, 50, 20,  // head (a loop), bottom point 2
      60, 55, 85, 45, 35, 60, 50, 85, 70, 85;  // hip 4; hands 5, 6 (arms from the head's point 2); feet 7, 8
  figure.closed = false;
  figure.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {2, 4}, {2, 5}, {2, 6}, {4, 7}, {4, 8}};
  validateCage(figure);
  const auto build = [&](OutsideMode mode) {
    WarpMeshOptions o;
    o.outside = mode;
    o.spacing = 2.0;
    WarpMesh mesh(120, 100, figure, o);
    // The field: the edge data at the nearest cage point (rows sum to 1, values in [0, 1]).
    Weights W(mesh.restVertices().rows(), figure.size());
    for (Index v = 0; v < W.rows(); ++v) W.row(v) = edgeDataAt(figure, mesh.restVertices().row(v)).transpose();
    mesh.setWeights(W);
    return mesh;
  };
  WarpMesh pinned = build(OutsideMode::Pinned), field = build(OutsideMode::Deform);
  const ExteriorWeights& E = *pinned.exteriorWeights();
  ASSERT_TRUE(E.needsFieldData());
  EXPECT_GT(E.report.band, 50);
  EXPECT_GE(E.report.minWeight, -1e-12);
  EXPECT_LE(E.report.maxWeight, 1.0 + 1e-12);
  Pose pose = restPose(figure.size());
  pose[5] = {Vec2(3, -12), 0.3};  // the right arm's hand up
  pose[7] = {Vec2(-4, 2), 0.0};
  const DeformReport r = pinned.deform(pose);
  field.deform(pose);
  EXPECT_EQ(r.flippedTriangles, 0);
  // Both meshes share the grid's vertex numbering; the points on the cage follow it after.
  const auto xs = gridAxis(120, 2.0), ys = gridAxis(100, 2.0);
  const Index grid = Index(xs.size() * ys.size());
  Index checked = 0;
  for (Index v = 0; v < grid; ++v)
    if (E.band[std::size_t(v)]) {
      EXPECT_LT((pinned.deformedVertices().row(v) - field.deformedVertices().row(v)).norm(), 1e-9) << "band vertex " << v;
      ++checked;
    }
  EXPECT_EQ(checked, E.report.band);
  const Points& F = pinned.deformedVertices();
  const Points& R = pinned.restVertices();
  for (const Index corner : {Index(0), Index(xs.size() - 1), grid - Index(xs.size()), grid - 1})
    EXPECT_EQ((F.row(corner) - R.row(corner)).norm(), 0.0);
}

/// While a point is dragged (DeformPass::Live), each repair of the background's folds continues from
/// the last picture when that one had no fold, and ends fold-free; a final pass starts from rest.
/// The L's arm corner (control 3) pulled past its distance to the border folds the harmonic
/// background next to it (see armPose).
TEST(PinnedOutside, ALiveDragRepairsFromTheLastFoldFreePicture) {
  WarpMesh mesh = meshWithMeanValue(lCage(), OutsideMode::Pinned);
  Pose pose = restPose(8);
  int folding = 0;
  for (int k = 1; k <= 12; ++k) {
    pose[3] = {Vec2(2.0 * k, -2.0 * k), 0.0};
    const DeformReport r = mesh.deform(pose, DeformPass::Live);
    EXPECT_EQ(r.repairedFolds, 0) << "step " << k;
    if (r.harmonicFolds == 0) continue;
    ++folding;
    EXPECT_TRUE(r.repairWarmStart) << "step " << k << ": the picture before had no fold";
  }
  ASSERT_GE(folding, 3) << "the drag must fold the harmonic background for this test to mean anything";
  const DeformReport final = mesh.deform(pose, DeformPass::Final);
  EXPECT_GT(final.harmonicFolds, 0);
  EXPECT_EQ(final.repairedFolds, 0);
  EXPECT_FALSE(final.repairWarmStart);
}

TEST(PinnedOutside, ParsesAndIsTheDefault) {
  OutsideMode m = OutsideMode::Deform;
  EXPECT_TRUE(parseName("pinned", m));
  EXPECT_EQ(m, OutsideMode::Pinned);
  EXPECT_EQ(toString(OutsideMode::Pinned), "pinned");
  EXPECT_EQ(WarpMeshOptions{}.outside, OutsideMode::Pinned);
  // The anchor column rides along: m + 1 columns, and a copy shares the exterior solution.
  WarpMesh mesh = meshWithMeanValue(lCage(), OutsideMode::Pinned);
  EXPECT_EQ(mesh.weights().cols(), 9);
  const WarpMesh copy = mesh;
  EXPECT_EQ(copy.exteriorWeights(), mesh.exteriorWeights());
}

}  // namespace
}  // namespace kc
