// The pinned mode's fold repair (exterior_untangle.h): random poses that push the cage towards the
// image border fold the plain harmonic extension outside the cage; after the repair nothing folds
// where a fold-free map exists (the deformed cage simple and inside the frame), the border and the
// corners stay, the inside and the cage are untouched, and a pose that folds nothing is unchanged.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "kc/core/outside_motion.h"
#include "kc/core/warp_mesh.h"
#include "warp_fixtures.h"
#include "random_point.h"

namespace kc {
namespace {

WarpMesh pinnedMesh(const Cage& cage, bool repair, int width = 120, int height = 100) {
  WarpMeshOptions o;
  o.outside = OutsideMode::Pinned;
  o.repairFolds = repair;
  WarpMesh mesh(width, height, cage, o);
  mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
  return mesh;
}

/// Random poses (seeded): each control moves by up to ±`reach` px (and turns by up to ±`turn`
/// rad) with probability 1/2, else stays.
std::vector<Pose> randomPoses(Index m, int count, double reach, double turn, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> move(-reach, reach), angle(-turn, turn), coin(0.0, 1.0);
  std::vector<Pose> poses;
  for (int k = 0; k < count; ++k) {
    Pose p = restPose(m);
    for (auto& h : p)
      if (coin(rng) < 0.5) h = {test::randomPoint(move, rng), turn > 0.0 ? angle(rng) : 0.0};
    poses.push_back(p);
  }
  return poses;
}

bool segmentsCross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const auto orient = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    return (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
  };
  return orient(a, b, c) * orient(a, b, d) < 0.0 && orient(c, d, a) * orient(c, d, b) < 0.0;
}

/// A fold-free pinned map exists only when the deformed cage is a simple polygon inside the frame
/// (with room for a triangle between them). Translations only: mean value weights are linear
/// along the cage's edges, so the deformed cage is the polygon of the moved controls.
bool roomForAFoldFreeMap(const Points& P, int width, int height, double margin) {
  const Index m = P.rows();
  for (Index i = 0; i < m; ++i) {
    if (P(i, 0) < margin || P(i, 1) < margin || P(i, 0) > width - 1 - margin || P(i, 1) > height - 1 - margin) return false;
    for (Index j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;
      if (segmentsCross(P.row(i), P.row((i + 1) % m), P.row(j), P.row((j + 1) % m))) return false;
    }
  }
  return true;
}

/// The repaired mesh against the plain one on `poses`: returns {poses that folded plainly,
/// those with room for a fold-free map}; checks what the repair may and may not change.
std::pair<int, int> checkRepair(const Cage& cage, const std::vector<Pose>& poses, int width, int height, bool expectNone) {
  WarpMesh repaired = pinnedMesh(cage, true, width, height), plain = pinnedMesh(cage, false, width, height);
  const ExteriorWeights& E = *repaired.exteriorWeights();
  const Points& R = repaired.restVertices();
  int folded = 0, room = 0, fixedFolds = 0;
  struct {
    Index folds = 0, moved = 0;  // triangles folded after the repair; of those, moved off the harmonic map
  } partial;
  Index before = 0, after = 0;
  for (const Pose& pose : poses) {
    const DeformReport r = repaired.deform(pose);
    plain.deform(pose);
    const OutsideMotion om = measureOutside(repaired), op = measureOutside(plain);
    EXPECT_EQ(r.harmonicFolds, op.flippedOutside);
    EXPECT_EQ(r.repairedFolds, om.flippedOutside);
    EXPECT_LE(om.flippedOutside, op.flippedOutside);
    EXPECT_EQ(om.cornerMax, 0.0);
    folded += op.flippedOutside > 0;
    before += op.flippedOutside;
    after += om.flippedOutside;
    // A triangle outside the cage with its three corners on the cage folds with the cage alone:
    // no placement of the free vertices unfolds it (ExteriorRepairReport::foldedFixed).
    bool foldsOnTheCage = false;
    for (Index t = 0; t < plain.outsideTriangles(); ++t) {
      const auto& tri = plain.triangles()[std::size_t(t)];
      foldsOnTheCage |= plain.jacobians()(t) <= 0.0 && !E.exterior[std::size_t(tri[0])] && !E.exterior[std::size_t(tri[1])] &&
                        !E.exterior[std::size_t(tri[2])];
    }
    fixedFolds += foldsOnTheCage;
    const bool fits = !foldsOnTheCage && roomForAFoldFreeMap(posedControls(cage.C, pose), width, height, 3.0);
    room += fits && op.flippedOutside > 0;
    if (expectNone && fits) {
      EXPECT_EQ(om.flippedOutside, 0) << "the deformed cage leaves room, yet folds remain (harmonic: " << r.harmonicFolds << ")";
    }
    Index moved = 0, inward = 0;  // inside and on the cage nothing moves; the border only slides or moves outward
    for (Index v = 0; v < R.rows(); ++v) {
      const Vec2 d = repaired.deformedVertices().row(v) - plain.deformedVertices().row(v);
      if (!E.exterior[std::size_t(v)]) moved += d != Vec2::Zero();
      const Vec2 n(R(v, 0) == -0.5 ? -1.0 : (R(v, 0) == width - 0.5 ? 1.0 : 0.0), R(v, 1) == -0.5 ? -1.0 : (R(v, 1) == height - 0.5 ? 1.0 : 0.0));
      inward += n != Vec2::Zero() && n.dot(d) < -1e-9;
    }
    EXPECT_EQ(moved, 0);
    EXPECT_EQ(inward, 0);
    // A part of the background the repair cannot untangle keeps the harmonic map: every triangle
    // that still folds lies where the harmonic map put it (a partial repair spread the squeeze over
    // the background and dragged the border, to leave one fold instead of twenty).
    for (Index t = 0; t < repaired.outsideTriangles(); ++t) {
      if (repaired.jacobians()(t) > 0.0) continue;
      ++partial.folds;
      for (int v : repaired.triangles()[std::size_t(t)])
        if (repaired.deformedVertices().row(v) != plain.deformedVertices().row(v)) {
          ++partial.moved;
          break;
        }
    }
  }
  EXPECT_EQ(partial.moved, 0) << "of " << partial.folds << " triangles folded after the repair";
  std::printf("%zu poses: %d folded the harmonic exterior (%ld triangles), %d of them with room for a fold-free map; "
              "%ld triangles folded after the repair; %d poses folded a triangle with its corners on the cage\n",
              poses.size(), folded, long(before), room, long(after), fixedFolds);
  return {folded, room};
}

TEST(ExteriorRepair, RandomTranslationsFoldNothingWhereTheCageLeavesRoom) {
  const Cage cage = lCage();
  const auto [folded, room] = checkRepair(cage, randomPoses(cage.size(), 60, 25.0, 0.0, 7), 120, 100, true);
  EXPECT_GT(room, 5) << "the poses should fold the plain extension where a fold-free map exists, or the test shows nothing";
}

TEST(ExteriorRepair, RandomPosesWithTurnsNeverAddFolds) {
  const Cage cage = lCage();
  const auto [folded, room] = checkRepair(cage, randomPoses(cage.size(), 30, 30.0, 0.6, 3), 120, 100, false);
  EXPECT_GT(folded, 5);
}

/// A photo-like picture's cage: a non-convex figure with a head, two arms and a notch, well inside
/// a wider frame, dragged by translations.
TEST(ExteriorRepair, NonConvexCageInAWideFrame) {
  Points C(12, 2);
  C << 100, 20, 130, 20, 132, 60, 180, 62, 182, 80, 132, 84, 140, 150, 116, 150, 112, 100, 100, 150, 80, 150, 98, 60;
  const Cage cage = Cage::polygon(C);
  const auto [folded, room] = checkRepair(cage, randomPoses(cage.size(), 40, 30.0, 0.0, 11), 240, 180, true);
  EXPECT_GT(room, 3);
}

/// Poses that push the L cage's right arm past the image's right border: no map with the whole
/// border pinned is one-to-one there; the border gives way (slides or moves outward) near the
/// crossing only, the corners stay, the inside and the cage do not change, and nothing folds.
TEST(ExteriorRepair, TheBorderGivesWayWhereTheCageCrossesIt) {
  const Cage cage = lCage();
  const int width = 120, height = 100;
  WarpMesh repaired = pinnedMesh(cage, true, width, height), plain = pinnedMesh(cage, false, width, height);
  const ExteriorWeights& E = *repaired.exteriorWeights();
  const Points& R = repaired.restVertices();
  const std::vector<std::vector<std::pair<int, Vec2>>> moves = {
      {{3, Vec2(18, 0)}, {4, Vec2(18, -10)}}, {{3, Vec2(25, 4)}, {4, Vec2(16, -6)}}, {{2, Vec2(10, -4)}, {3, Vec2(22, -2)}}};
  for (const auto& move : moves) {
    Pose pose = restPose(cage.size());
    for (const auto& [i, d] : move) pose[std::size_t(i)].translate = d;
    const Points P = posedControls(cage.C, pose);
    ASSERT_GT(P.col(0).maxCoeff(), width - 0.5) << "the pose should push the cage past the border";
    const DeformReport r = repaired.deform(pose);
    plain.deform(pose);
    const OutsideMotion om = measureOutside(repaired), op = measureOutside(plain);
    EXPECT_GT(op.flippedOutside, 0) << "the pinned border should fold the harmonic map";
    EXPECT_EQ(om.flippedOutside, 0) << "harmonic folds " << r.harmonicFolds;
    EXPECT_EQ(om.cornerMax, 0.0);
    EXPECT_GT(om.borderMoved, 0);
    Index moved = 0, inward = 0, farBorder = 0;
    for (Index v = 0; v < R.rows(); ++v) {
      const Vec2 d = repaired.deformedVertices().row(v) - plain.deformedVertices().row(v);
      if (!E.exterior[std::size_t(v)]) moved += d != Vec2::Zero();
      if (R(v, 0) == width - 0.5) inward += d.x() < -1e-9;
      // The left and top sides are far from the crossing: bit-identical to the harmonic map.
      if (R(v, 0) == -0.5 || R(v, 1) == -0.5) farBorder += d != Vec2::Zero();
    }
    EXPECT_EQ(moved, 0);
    EXPECT_EQ(inward, 0);
    EXPECT_EQ(farBorder, 0);
  }
}

TEST(ExteriorRepair, APoseThatFoldsNothingIsUnchanged) {
  const Cage cage = lCage();
  WarpMesh repaired = pinnedMesh(cage, true), plain = pinnedMesh(cage, false);
  int checked = 0;
  for (const Pose& pose : randomPoses(cage.size(), 20, 4.0, 0.2, 3)) {
    const DeformReport p = plain.deform(pose);
    const DeformReport r = repaired.deform(pose);
    if (p.flippedTriangles > 0) continue;  // (a small move can still fold a sliver next to the cage)
    ++checked;
    EXPECT_EQ(r.harmonicFolds, 0);
    EXPECT_EQ(r.repairVertices, 0);
    EXPECT_EQ(repaired.deformedVertices(), plain.deformedVertices());
  }
  EXPECT_GT(checked, 10);
}

/// The L cage's pinned mesh (mean value weights, no repair) with what repairExteriorFolds takes:
/// the vertices outside the cage, the topology with the frame, and the exterior triangles' signed
/// rest areas.
struct RepairSetup {
  static constexpr int width = 120, height = 100;
  Cage cage = lCage();
  WarpMesh plain = pinnedMesh(cage, false, width, height);
  const Points& rest = plain.restVertices();
  const Triangles& T = plain.triangles();
  Index nt = plain.outsideTriangles();
  std::vector<std::uint8_t> movable;
  ExteriorRepairTopology topo;
  Eigen::VectorXd area;

  RepairSetup() : movable(std::size_t(rest.rows())), area(nt) {
    for (Index v = 0; v < rest.rows(); ++v) movable[std::size_t(v)] = plain.exteriorWeights()->exterior[std::size_t(v)];
    const ExteriorRepairFrame frame{-0.5, -0.5, width - 0.5, height - 0.5};
    topo = exteriorRepairTopology(rest, T, nt, movable, &frame);
    for (Index t = 0; t < nt; ++t) area(t) = signedArea(rest, t);
  }
  double signedArea(const Points& P, Index t) const {
    const auto& [a, b, c] = T[std::size_t(t)];
    return 0.5 * ((P(b, 0) - P(a, 0)) * (P(c, 1) - P(a, 1)) - (P(b, 1) - P(a, 1)) * (P(c, 0) - P(a, 0)));
  }
  double jacobian(const Points& P, Index t) const { return signedArea(P, t) / area(t); }
};

/// The relaxation (exterior_relax.h) after the untangling: on poses with turns that fold the
/// harmonic exterior and that the repair untangles, the smallest det J outside the cage rises
/// (the untangling alone stops at slivers just above its target), nothing folds, and only the
/// repaired region moves.
TEST(ExteriorRepair, TheRelaxationSpreadsTheSqueezeOverTheRegion) {
  RepairSetup setup;
  auto& [cage, plain, rest, T, nt, movable, topo, area] = setup;
  const auto minJacobian = [&](const Points& P) {
    double m = std::numeric_limits<double>::infinity();
    for (Index t = 0; t < nt; ++t) m = std::min(m, setup.jacobian(P, t));
    return m;
  };
  int compared = 0, raised = 0;
  double worstUntangled = 1.0, worstRelaxed = 1.0;
  for (const Pose& pose : randomPoses(cage.size(), 30, 30.0, 0.6, 3)) {
    plain.deform(pose);
    const Points harmonic = plain.deformedVertices();
    Points untangled = harmonic, relaxed = harmonic;
    ExteriorRepairOptions none;  // the continuation without its barrier: halving and untangling only
    none.stepRelaxSweeps = 0;
    none.relaxSweeps = 0;
    const ExteriorRepairReport u = repairExteriorFolds(rest, untangled, T, topo, nt, area, none);
    const ExteriorRepairReport r = repairExteriorFolds(rest, relaxed, T, topo, nt, area);
    if (u.foldedBefore == 0 || u.foldedAfter > 0) continue;
    ++compared;
    EXPECT_EQ(r.foldedAfter, 0);
    EXPECT_GT(r.relaxSweeps, 0);
    const double ju = minJacobian(untangled), jr = minJacobian(relaxed);
    EXPECT_GT(jr, 0.0);
    raised += jr > ju;
    worstUntangled = std::min(worstUntangled, ju);
    worstRelaxed = std::min(worstRelaxed, jr);
    for (Index v = 0; v < rest.rows(); ++v)  // only free vertices of the region move
      if (!topo.free[std::size_t(v)]) {
        EXPECT_EQ(relaxed.row(v), harmonic.row(v)) << "vertex " << v;
      }
  }
  std::printf("%d untangled poses: the relaxation raised the smallest det J on %d; worst %.3g untangled, %.3g relaxed\n", compared,
              raised, worstUntangled, worstRelaxed);
  EXPECT_GT(compared, 5);
  EXPECT_GE(raised, compared * 9 / 10);
  EXPECT_GT(worstRelaxed, 2.0 * worstUntangled);
}

/// Where the field's map turns a piece of the cage's outline back (its weights along the cage are
/// not linear, as a kernel field's are not), the background triangle on that piece folds wherever
/// its free vertex goes outside the deformed inside. Such a fold next to folds the repair can
/// untangle: the repair untangles those and leaves this one as the harmonic map put it, reported
/// in foldedForced (it once spent its budget on it and reverted the whole region).
TEST(ExteriorRepair, AFoldTheOutlineForcesDoesNotStopTheRepairBesideIt) {
  RepairSetup setup;
  auto& [cage, plain, rest, T, nt, movable, topo, area] = setup;
  const auto folded = [&](const Points& P, Index t) { return !(setup.jacobian(P, t) > 0.0); };
  const auto onCage = [&](int v) {
    return !movable[std::size_t(v)] && topo.start[std::size_t(v) + 1] > topo.start[std::size_t(v)];
  };
  // Points w, v, u on the cage in a row along one cage edge (v–u and w–v edges of the background).
  const auto pieceAfter = [&](int v, int u) {
    const Vec2 r = rest.row(u) - rest.row(v);
    for (Index k = topo.start[std::size_t(v)]; k < topo.start[std::size_t(v) + 1]; ++k)
      if (topo.around[std::size_t(k)] < nt)
        for (int w : T[std::size_t(topo.around[std::size_t(k)])]) {
          const Vec2 q = rest.row(v) - rest.row(w);
          if (w != v && onCage(w) && q.dot(r) > 0.0 && std::abs(q.x() * r.y() - q.y() * r.x()) < 1e-9 * q.norm() * r.norm())
            return w;
        }
    return -1;
  };
  int tried = 0;
  for (const Pose& pose : randomPoses(cage.size(), 30, 30.0, 0.0, 7)) {
    plain.deform(pose);
    const Points harmonic = plain.deformedVertices();
    Points repaired = harmonic;
    const ExteriorRepairReport clean = repairExteriorFolds(rest, repaired, T, topo, nt, area);
    if (clean.foldedBefore == 0 || clean.foldedAfter > 0) continue;
    // A point on the cage next to the repaired region, pulled past its neighbour along the cage
    // edge: the piece between them turns back against the piece before it.
    int v = -1, u = -1;
    for (Index t = 0; t < nt && v < 0; ++t) {
      const auto& tri = T[std::size_t(t)];
      bool touchesRegion = false;
      for (int w : tri) touchesRegion |= repaired.row(w) != harmonic.row(w);
      if (!touchesRegion) continue;
      for (int k = 0; k < 3 && v < 0; ++k) {
        const int a = tri[std::size_t(k)], b = tri[std::size_t((k + 1) % 3)];
        if (onCage(a) && onCage(b) && pieceAfter(a, b) >= 0) v = a, u = b;
      }
    }
    if (v < 0) continue;
    Points entry = harmonic;
    entry.row(v) = harmonic.row(u) + 0.5 * (harmonic.row(u) - harmonic.row(v));
    Points out = entry;
    const ExteriorRepairReport r = repairExteriorFolds(rest, out, T, topo, nt, area);
    ++tried;
    EXPECT_GT(r.foldedForced, 0);
    EXPECT_EQ(r.foldedAfter, r.foldedForced) << "pose " << tried << ": harmonic folds " << r.foldedBefore;
    EXPECT_GT(r.regionVertices, 0);
    // What still folds is on the turned-over piece, as the harmonic map put it.
    for (Index t = 0; t < nt; ++t) {
      if (!folded(out, t)) continue;
      for (int w : T[std::size_t(t)]) EXPECT_EQ(out.row(w), entry.row(w)) << "triangle " << t;
    }
    if (tried == 5) break;
  }
  EXPECT_EQ(tried, 5);
}

}  // namespace
}  // namespace kc
