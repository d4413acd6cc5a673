// The pinned mode's fold guard: random poses that push the cage towards (and over) the image
// border fold the plain harmonic extension outside the cage; with the guard nothing folds there,
// the border stays, the inside is untouched, and a pose that folds nothing is not changed.
#include <gtest/gtest.h>

#include <random>

#include "kc/core/outside_motion.h"
#include "kc/core/warp_mesh.h"
#include "warp_fixtures.h"

namespace kc {
namespace {

WarpMesh pinnedMesh(const Cage& cage, bool guard) {
  WarpMeshOptions o;
  o.outside = OutsideMode::Pinned;
  o.foldGuard = guard;
  WarpMesh mesh(120, 100, cage, o);
  mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
  return mesh;
}

/// Random poses (seeded): each control moves by up to ±`reach` px and turns by up to ±0.6 rad
/// with probability 1/2, else stays.
std::vector<Pose> randomPoses(Index m, int count, double reach, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> move(-reach, reach), turn(-0.6, 0.6), coin(0.0, 1.0);
  std::vector<Pose> poses;
  for (int k = 0; k < count; ++k) {
    Pose p = restPose(m);
    for (auto& h : p)
      if (coin(rng) < 0.5) h = {Vec2(move(rng), move(rng)), turn(rng)};
    poses.push_back(p);
  }
  return poses;
}

TEST(FoldGuard, RandomPosesFoldNothingOutsideTheCage) {
  const Cage cage = lCage();
  WarpMesh guarded = pinnedMesh(cage, true), plain = pinnedMesh(cage, false);
  const ExteriorWeights& E = *guarded.exteriorWeights();
  Index plainFolds = 0, posesThatFolded = 0;
  for (const Pose& pose : randomPoses(cage.size(), 40, 30.0, 7)) {
    const DeformReport g = guarded.deform(pose);
    plain.deform(pose);
    const OutsideMotion og = measureOutside(guarded), op = measureOutside(plain);
    plainFolds += op.flippedOutside;
    posesThatFolded += op.flippedOutside > 0;
    EXPECT_EQ(og.flippedOutside, 0) << "guard folds " << g.guardFolds << ", held back " << g.guardVertices;
    EXPECT_EQ(og.cornerMax, 0.0);
    EXPECT_GE(g.guardFolds, op.flippedOutside) << "the guard sees every fold (det J ≤ 0.05 ⊇ det J ≤ 0)";
    // Only vertices outside the cage are held back; each moves along its own displacement, less far.
    for (Index v = 0; v < guarded.restVertices().rows(); ++v) {
      const Vec2 r = guarded.restVertices().row(v), a = guarded.deformedVertices().row(v), b = plain.deformedVertices().row(v);
      if (!E.exterior[std::size_t(v)]) {
        ASSERT_EQ(a, b) << "inside the cage the guard changes nothing";
        continue;
      }
      ASSERT_LE((a - r).norm(), (b - r).norm() + 1e-9);
      ASSERT_LT(std::abs((a - r).x() * (b - r).y() - (a - r).y() * (b - r).x()), 1e-6 * (1.0 + (b - r).squaredNorm()));
    }
  }
  std::printf("40 random poses: %ld folded the plain pinned exterior (%ld triangles); 0 with the guard\n",
              long(posesThatFolded), long(plainFolds));
  EXPECT_GT(posesThatFolded, 5) << "the poses should reach the border, or the test shows nothing";
}

TEST(FoldGuard, APoseThatFoldsNothingIsUnchanged) {
  const Cage cage = lCage();
  WarpMesh guarded = pinnedMesh(cage, true), plain = pinnedMesh(cage, false);
  int checked = 0;
  for (const Pose& pose : randomPoses(cage.size(), 20, 4.0, 3)) {
    const DeformReport g = guarded.deform(pose);
    const DeformReport p = plain.deform(pose);
    if (p.minJacobian <= 0.05) continue;  // (a small move can still fold at a corner)
    ++checked;
    EXPECT_EQ(g.guardFolds, 0);
    EXPECT_EQ(g.guardVertices, 0);
    EXPECT_EQ(guarded.deformedVertices(), plain.deformedVertices());
  }
  EXPECT_GT(checked, 10);
}

}  // namespace
}  // namespace kc
