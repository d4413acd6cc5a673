// The pinned outside mode's fade: the background's motion dies out within a band around the cage
// that grows with the drag, so what lies far from the cage stays where it was, without folds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "kc/core/deform.h"
#include "kc/core/warp_mesh.h"
#include "warp_fixtures.h"

namespace kc {
namespace {

constexpr int kWidth = 800, kHeight = 600;

/// A person (23 points, 190×330 px) standing in the middle of an 800×600 picture, legs 8 px apart
/// at the crotch. Control 5 is the right hand, 9 the right foot (135 px above the bottom border).
Cage personCage() {
  Points C(23, 2);
  C << 400, 135, 428, 150, 432, 185, 414, 203, 470, 215, 525, 300, 508, 312, 458, 250, 452, 330, 462, 465, 432, 465,
      404, 362, 396, 362, 368, 465, 338, 465, 348, 330, 342, 250, 292, 312, 275, 300, 330, 215, 386, 203, 368, 185,
      372, 150;
  return Cage::polygon(C);
}

/// What a drag does to the background (per pixel centre, displacement interpolated on the rest mesh).
struct Motion {
  double farMovedFraction = 0.0;  ///< Of the pixels outside the cage farther than `far` from it, those moving ≥ 1 px.
  double farMax = 0.0;            ///< Their largest displacement (px).
  double borderMax = 0.0;         ///< Largest displacement of a mesh vertex on the image border.
  double squeeze = 1.0;           ///< Smallest det J over the triangles outside the cage.
  Index flipped = 0;              ///< Triangles with det J ≤ 0 outside the cage.
  double fadeWidth = 0.0;
};

Motion drag(double fadeBand, Index control, const Vec2& d, double far = 120.0) {
  const Cage cage = personCage();
  WarpMeshOptions o;
  o.fadeBand = fadeBand;
  WarpMesh mesh(kWidth, kHeight, cage, o);
  mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
  Pose pose = restPose(cage.size());
  pose[std::size_t(control)].translate = d;
  const DeformReport rep = mesh.deform(pose);
  Motion m;
  m.fadeWidth = rep.fadeWidth;
  const Points& R = mesh.restVertices();
  const Points& F = mesh.deformedVertices();
  for (Index v = 0; v < R.rows(); ++v) {
    const Vec2 x = R.row(v);
    if (x.x() <= -0.5 || x.y() <= -0.5 || x.x() >= kWidth - 0.5 || x.y() >= kHeight - 0.5)
      m.borderMax = std::max(m.borderMax, (F.row(v) - R.row(v)).norm());
  }
  for (Index t = 0; t < mesh.outsideTriangles(); ++t) {
    m.squeeze = std::min(m.squeeze, mesh.jacobians()(t));
    m.flipped += mesh.jacobians()(t) <= 0.0 ? 1 : 0;
  }
  // Displacement per pixel centre: barycentric on the rest triangle holding it (first one wins).
  std::vector<double> moved(std::size_t(kWidth) * kHeight, -1.0);
  for (const auto& t : mesh.triangles()) {
    const Vec2 a = R.row(t[0]), b = R.row(t[1]), c = R.row(t[2]);
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (area == 0.0) continue;
    const int x0 = std::max(0, int(std::ceil(std::min({a.x(), b.x(), c.x()})))), x1 = std::min(kWidth - 1, int(std::max({a.x(), b.x(), c.x()})));
    const int y0 = std::max(0, int(std::ceil(std::min({a.y(), b.y(), c.y()})))), y1 = std::min(kHeight - 1, int(std::max({a.y(), b.y(), c.y()})));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        double& out = moved[std::size_t(y) * kWidth + x];
        if (out >= 0.0) continue;
        const Vec2 p(x, y);
        const auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
        const double l0 = cross(b - p, c - p) / area, l1 = cross(c - p, a - p) / area, l2 = 1.0 - l0 - l1;
        if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
        const Vec2 f = l0 * Vec2(F.row(t[0])) + l1 * Vec2(F.row(t[1])) + l2 * Vec2(F.row(t[2]));
        out = (f - p).norm();
      }
  }
  const CageQueries queries(cage);
  Index farPixels = 0, farMoved = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const Vec2 p(x, y);
      if (queries.inside(p) || queries.distance(p) <= far) continue;
      const double u = moved[std::size_t(y) * kWidth + x];
      ++farPixels;
      farMoved += u >= 1.0 ? 1 : 0;
      m.farMax = std::max(m.farMax, u);
    }
  m.farMovedFraction = double(farMoved) / double(std::max<Index>(1, farPixels));
  return m;
}

struct Drag {
  const char* name;
  Index control;
  Vec2 d;
};

const Drag kDrags[] = {{"hand right", 5, Vec2(60, 0)}, {"hand up", 5, Vec2(0, -60)}, {"hand down", 5, Vec2(0, 60)},
                       {"foot down", 9, Vec2(0, 60)}, {"foot right", 9, Vec2(60, 0)}};

TEST(OutsideFade, FarBackgroundStaysAfterASixtyPixelDrag) {
  for (const Drag& g : kDrags) {
    const Motion before = drag(0.0, g.control, g.d), after = drag(WarpMeshOptions{}.fadeBand, g.control, g.d);
    std::printf("%-10s  far (>120 px) moving >= 1 px: %5.2f%% -> %5.2f%% (max %5.2f -> %5.2f px)  "
                "smallest det J outside: %.3f -> %.3f  folds outside %ld -> %ld  band %.0f px\n",
                g.name, 100 * before.farMovedFraction, 100 * after.farMovedFraction, before.farMax, after.farMax,
                before.squeeze, after.squeeze, long(before.flipped), long(after.flipped), after.fadeWidth);
    EXPECT_LE(after.farMovedFraction, 0.02) << g.name;
    EXPECT_EQ(after.flipped, 0) << g.name << ": no fold outside the cage";
    EXPECT_EQ(after.borderMax, 0.0) << g.name << ": the image border stays";
    EXPECT_DOUBLE_EQ(after.fadeWidth, 2.0 * 60.0) << g.name << ": the band is twice the outline's largest move";
    // Smooth: next to the cage the squeeze is the harmonic extension's (the moved hand's convex
    // corners), which the fade barely deepens.
    EXPECT_GT(after.squeeze, 0.75 * before.squeeze) << g.name;
  }
}

TEST(OutsideFade, OffTheStretchReachesFarBackground) {
  // Without the fade the harmonic extension moves background far from the cage.
  const Motion before = drag(0.0, 5, Vec2(60, 0));
  EXPECT_GT(before.farMovedFraction, 0.02);
  EXPECT_EQ(before.fadeWidth, 0.0);
}

TEST(OutsideFade, NextToTheCageTheStretchIsTheHarmonicOne) {
  // φ = 1 with zero slope at the cage: within a few pixels of the moved hand the background moves
  // with the outline as without the fade.
  const Cage cage = personCage();
  WarpMeshOptions faded, plain;
  plain.fadeBand = 0.0;
  faded.repairFolds = plain.repairFolds = false;  // the fade alone
  WarpMesh a(kWidth, kHeight, cage, faded), b(kWidth, kHeight, cage, plain);
  a.setWeights(meanValueWeights(cage.C, a.restVertices()));
  b.setWeights(meanValueWeights(cage.C, b.restVertices()));
  Pose pose = restPose(cage.size());
  pose[5].translate = Vec2(60, 0);
  a.deform(pose);
  b.deform(pose);
  const CageQueries queries(cage);
  double gap = 0.0;
  for (Index v = 0; v < a.restVertices().rows(); ++v) {
    const Vec2 x = a.restVertices().row(v);
    if (!a.exteriorWeights()->exterior[std::size_t(v)] || queries.distance(x) > 6.0) continue;
    const double g = (a.deformedVertices().row(v) - b.deformedVertices().row(v)).norm();
    gap = std::max(gap, g);
  }
  EXPECT_LT(gap, 0.04 * 60.0);
}

}  // namespace
}  // namespace kc
