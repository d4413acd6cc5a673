// Structure lines in the kernel backend (thesis 5.3): straightness, parallelism, partition of
// unity and reproduction along random lines in the bundled star; sessions keep the lines.

#include <gtest/gtest.h>

#include "structure_refusal.h"

#include <Eigen/Dense>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

#include "cli_run.h"
#include "kc/app/backend.h"
#include "kc/app/errors.h"
#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/line_metrics.h"
#include "kc/app/pipeline.h"
#include "kc/app/structure.h"
#include "kc/core/deform.h"
#include "kc/core/field/kernel_field.h"
#include "kc/core/structure/lines.h"

namespace kc::app {
namespace {

Cage starCage() { return loadCage(std::string(KC_SOURCE_DIR) + "/images/star.cage.json"); }

/// n points from a to b, ends included.
Points along(const StructureLine& l, Index n) {
  Points P(n, 2);
  for (Index k = 0; k < n; ++k) {
    const double t = double(k) / double(n - 1);
    P.row(k) = ((1.0 - t) * l.a + t * l.b).transpose();
  }
  return P;
}

/// Grid points every `step` px in [from, to)² that lie inside the cage.
Points gridInside(const Cage& cage, double from, double to, double step) {
  Points G(0, 2);
  for (double y = from; y < to; y += step)
    for (double x = from; x < to; x += step)
      if (insideCage(cage, Vec2(x, y))) {
        G.conservativeResize(G.rows() + 1, 2);
        G.row(G.rows() - 1) << x, y;
      }
  return G;
}

LineFigures measure(const Session& s, const std::vector<StructureLine>& lines, int trials) {
  return measureLines(s, lines, trials);
}

TEST(StructureLinesSlow, RandomLinesStayStraightAndParallelUnderTranslations) {
  const Cage cage = starCage();
  Structure st;
  st.lines = randomLines(cage, 3, 100.0, 150.0, BindParams{}.spacing, 11, RandomLineLayout::ParallelPair);
  st.groups = {"pair"};
  const Session plain = bind(cage, 320, 320, BindParams{});
  const LineFigures before = measure(plain, st.lines, 20);
  EXPECT_GT(before.deviation, 1.0);  // the measure can fail: without the structure the same lines bend by pixels
  // Exact lines (the default: the field's correction, to round-off), then lines made linear through
  // their samples (sessions written before it: within 0.1 px).
  for (const bool exact : {true, false}) {
    BindParams p;
    p.kc.exactLines = exact;
    const Session lined = bind(cage, st, 320, 320, p);
    EXPECT_EQ(lined.samples.lines.size(), exact ? 0u : 3u);
    const LineFigures after = measure(lined, st.lines, 20);
    EXPECT_LE(after.deviation, exact ? 1e-9 : 0.1) << "bent by " << after.deviation << " px (without lines: " << before.deviation << ")";
    EXPECT_LE(after.angle, 0.05) << "parallel pair at " << after.angle << " degrees (without: " << before.angle << ")";
    EXPECT_LE(after.unity, 1e-9);
    EXPECT_LE(after.reproduction, 1e-9);
    std::printf("lines (exact %d): deviation %.3g px (without %.3g), parallel angle %.3g deg (without %.3g), unity %.2g, reproduction %.2g\n",
                int(exact), after.deviation, before.deviation, after.angle, before.angle, after.unity, after.reproduction);

    // Partition of unity and reproduction everywhere inside the cage, not only on the lines.
    const Points G = gridInside(cage, 20, 300, 7);
    const Weights WG = lined.field->weightsAt(G);
    EXPECT_LE((WG.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-9);
    EXPECT_LE((WG * cage.C - G).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(StructureLinesSlow, SessionKeepsTheLinesAndTheirWeights) {
  const auto dir = test::scratchDir("lines_session");
  const Cage cage = starCage();
  BindParams p;
  Structure st;
  st.lines = randomLines(cage, 2, 100.0, 130.0, p.spacing, 5, RandomLineLayout::ParallelPair);
  st.groups = {"g"};
  const Session s = bind(cage, st, 320, 320, p);
  const std::string path = (dir / "lines.kcw.json").string();
  saveSession(path, s);
  const Session t = loadSession(path);
  ASSERT_EQ(t.structure.lines.size(), 2u);
  EXPECT_EQ(t.structure.groups, st.groups);
  EXPECT_EQ(t.samples.lines, s.samples.lines);
  EXPECT_EQ(t.structure.lines[1].group, 0);
  const Points P = along(st.lines[0], 50);
  EXPECT_LE((t.field->weightsAt(P) - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LE(measure(t, st.lines, 5).deviation, 0.1);
}

TEST(StructureLinesSlow, ReoptimizingSamplesNearALineGivesTheBindsWeightsBack) {
  // A brush stroke re-optimizes a subset of samples; with unchanged targets the session must come
  // back to the bind's weights, also next to a line: with exact lines (the field's correction follows
  // the weights), and with sampled lines, as sessions written before them repaint (the neighbourhood
  // blend starts again from the optimizer's weights, not from its own earlier result).
  const Cage cage = starCage();
  Structure st;
  st.lines = randomLines(cage, 2, 100.0, 130.0, BindParams{}.spacing, 5);
  for (const bool exact : {true, false}) {
    BindParams p;
    p.kc.exactLines = exact;
    Session s = bind(cage, st, 320, 320, p);
    const Weights W = s.W;
    const Vec2 mid = 0.5 * (st.lines[0].a + st.lines[0].b);
    std::vector<Index> subset;
    for (Index i = 0; i < s.samples.size(); ++i)
      if ((s.samples.X.row(i).transpose() - mid).norm() < 15.0 && s.samples.kind[std::size_t(i)] == SampleKind::Interior)
        subset.push_back(i);
    ASSERT_GT(subset.size(), 5u);
    const auto t0 = std::chrono::steady_clock::now();
    reoptimize(s, s.params.kc.method, subset);
    std::printf("re-optimizing %zu samples next to a line (exact %d): %.1f ms (%ld samples, 2 lines)\n", subset.size(), int(exact),
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(), long(s.samples.size()));
    EXPECT_LE((s.W - W).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LE(measure(s, st.lines, 5).deviation, exact ? 1e-9 : 0.1);
  }
}

TEST(StructureLinesSlow, APaintedStrokeKeepsExactLinesStraight) {
  // The field's correction follows new weights by itself: a stroke that moves one control's targets
  // over a line's middle changes the weights there, and the lines stay straight to round-off.
  const Cage cage = starCage();
  BindParams p;
  Structure st;
  st.lines = randomLines(cage, 3, 100.0, 150.0, p.spacing, 11, RandomLineLayout::Crossing);
  Session s = bind(cage, st, 320, 320, p);
  const Vec2 mid = 0.5 * (st.lines[0].a + st.lines[0].b);
  const Points P = along(st.lines[0], 50);
  const Weights before = s.field->weightsAt(P);
  std::vector<Index> subset;
  for (Index i = 0; i < s.samples.size(); ++i)
    if ((s.samples.X.row(i).transpose() - mid).norm() < 25.0 && s.samples.kind[std::size_t(i)] == SampleKind::Interior) {
      subset.push_back(i);
      s.W0.row(i) = 0.6 * s.W0.row(i) + 0.4 * Eigen::RowVectorXd::Unit(cage.size(), 0);
    }
  ASSERT_GT(subset.size(), 5u);
  reoptimize(s, s.params.kc.method, subset);
  EXPECT_GT((s.field->weightsAt(P) - before).cwiseAbs().maxCoeff(), 1e-3) << "the stroke changed nothing on the line";
  const LineFigures f = measure(s, st.lines, 10);
  EXPECT_LE(f.deviation, 1e-9);
  EXPECT_LE(f.unity, 1e-9);
  EXPECT_LE(f.reproduction, 1e-9);
}

TEST(StructureLinesSlow, ALineAlongARigidRegionLeavesTheRegionAsTheRigidityMadeIt) {
  // The figure's rigid octagon (its head) with a line 2.6 px below its bottom side and one across it:
  // inside the octagon the field is the one the rigidity QP made (the correction stops at its sides,
  // as at the cage), and the line beside it is straight to round-off.
  const Cage cage = loadCage(std::string(KC_SOURCE_DIR) + "/images/figure.cage.json");
  Structure st = loadStructure(std::string(KC_SOURCE_DIR) + "/images/figure.structure.json");
  ASSERT_EQ(st.rigid.size(), 1u);
  const StructureLine beside{Vec2(140, 110), Vec2(180, 110)};
  st.lines.push_back(beside);
  st.lines.push_back({Vec2(120, 60), Vec2(200, 90)});
  Session s = bind(cage, st, 320, 400, BindParams{});
  const Points inside = gridInside(Cage::polygon(st.rigid[0].polygon), 45, 191, 2);
  ASSERT_GT(inside.rows(), 50);
  const Weights corrected = s.field->weightsAt(inside);
  auto* kernel = dynamic_cast<KernelField*>(s.field.get());
  ASSERT_TRUE(kernel && kernel->lineCorrection());
  const std::shared_ptr<const LineCorrection> correction = kernel->lineCorrection();
  kernel->setLineCorrection(nullptr);
  const Weights plain = kernel->weightsAt(inside);
  EXPECT_TRUE(corrected == plain) << "the correction reached into the rigid region";
  const double plainBend = measure(s, {beside}, 20).deviation;
  kernel->setLineCorrection(correction);
  EXPECT_LE(measure(s, {beside}, 20).deviation, 1e-9);
  EXPECT_GT(plainBend, 1e-3) << "the line beside the region is straight without the correction: the check above cannot fail";
}

TEST(StructureLinesSlow, ALongLineNearTheCageEdgeLeavesNoRingingAroundIt) {
  // A 420-px line 20 px inside the top edge of a picture-sized 8-point cage, its end 22 px from a
  // corner (a pin header along a circuit board's edge): at this cage's automatic spacing (14.5 px,
  // σ 12.8 px) the fit that makes the field linear along the line has to change from the line's
  // weights to the held edge samples' within 1.6σ. Fitted without regard to the samples around
  // the line, it rang: weights from −1.17 to 1.64 beside the line, the picture shredded there.
  Points C(8, 2);
  C << 4, 4, 360, 2, 716, 4, 716, 238, 716, 473, 360, 475, 4, 473, 4, 238;
  const Cage cage = Cage::polygon(C);
  BindParams p;
  p.spacing = 14.54;
  Structure st;
  st.lines = {StructureLine{Vec2(20, 24), Vec2(440, 24)}, StructureLine{Vec2(20, 452), Vec2(440, 452)}};
  const Session s = bind(cage, st, 720, 477, p);
  const Weights WG = s.field->weightsAt(gridInside(cage, 8, 712, 3));
  const LineFigures f = measure(s, st.lines, 20);
  std::printf("line by the edge: weights inside the cage in [%.3g, %.3g], bend %.3g px\n", WG.minCoeff(), WG.maxCoeff(),
              f.deviation);
  EXPECT_GE(WG.minCoeff(), -0.1);
  EXPECT_LE(WG.maxCoeff(), 1.1);
  EXPECT_LE(f.deviation, 0.1);
  EXPECT_LE((WG.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-9);
}

TEST(StructureLinesSlow, ALineEndingNearAConcaveCornerDoesNotFoldUnderADrag) {
  // Drawn in the window on a 548x342 photo: a 15-point cage over a player's torso, an X of lines
  // across it and a line along the lettering that ends 22 px from a concave corner of the cage; then
  // the corner below that one dragged 33 px to the right and the top-left point 30 px up and left.
  // A line fit that held the samples around the lines more loosely folded 6 triangles at the end of
  // the lettering line here (det J down to -0.52).
  Points C(15, 2), P(15, 2);
  C << 160, 118, 205, 105, 260, 110, 300, 122, 312, 150, 292, 162, 302, 215, 332, 238, 342, 266, 300, 276, 255, 271, 225, 262,
      220, 240, 190, 185, 175, 142;
  P = C;
  P.row(0) << 139.94, 94.8;
  P.row(6) << 335.23, 204.97;
  const Cage cage = Cage::polygon(C);
  Structure st;
  st.lines = {StructureLine{Vec2(204.4, 127.74), Vec2(284.66, 225.55)}, StructureLine{Vec2(221.96, 231.82), Vec2(279.64, 129.62)},
              StructureLine{Vec2(211.93, 159.71), Vec2(269.61, 159.71)}};
  const Session s = bind(cage, st, 548, 342, BindParams{});
  WarpMesh mesh = buildWarpMesh(s, warpMeshOptionsFor(s));
  const DeformReport r = mesh.deform(poseFromPositions(C, P));
  std::printf("lettering line by a concave corner: %ld flipped triangles, smallest det J %.3f, bend %.3g px\n", long(r.flippedTriangles),
              r.minJacobian, measure(s, st.lines, 20).deviation);
  EXPECT_EQ(r.flippedTriangles, 0);
  EXPECT_GT(r.minJacobian, 0.0);
}

TEST(StructureLines, FoldsAreCountedOverTheLineMeasuresPoses) {
  // measureFolds deforms the session's warp mesh by the poses measureLines uses: none at the rest
  // pose, some when every control of the star is thrown 150 px about.
  const Cage cage = loadCage(std::string(KC_SOURCE_DIR) + "/images/star.cage.json");
  BindParams p;
  p.spacing = 12.0;
  const Session s = bind(cage, 320, 320, p);
  const FoldFigures rest = measureFolds(s, 3, 0.0);
  EXPECT_EQ(rest.foldedPoses, 0);
  EXPECT_EQ(rest.flipped, 0);
  EXPECT_NEAR(rest.minJacobian, 1.0, 1e-9);
  const FoldFigures wild = measureFolds(s, 4, 150.0);
  EXPECT_GT(wild.foldedPoses, 0);
  EXPECT_GE(wild.flipped, wild.foldedPoses);
  EXPECT_LE(wild.minJacobian, 0.0);
  // The same seed draws the same poses, each control moved by at most the given amount.
  const std::vector<Points> a = randomTranslations(cage.size(), 4, 150.0, 7), b = randomTranslations(cage.size(), 4, 150.0, 7);
  ASSERT_EQ(a.size(), 4u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k], b[k]);
    EXPECT_LE(a[k].cwiseAbs().maxCoeff(), 150.0);
  }
  EXPECT_NE(a[0], a[1]);
}

TEST(StructureLines, AStructureWrittenAsJsonReadsBackTheSame) {
  Structure st;
  st.groups = {"rails"};
  st.lines = {StructureLine{Vec2(1.0 / 3.0, 2), Vec2(40, 2), 0}, StructureLine{Vec2(1, 9), Vec2(40, 9.125), 0},
              StructureLine{Vec2(5, 5), Vec2(6, 30), -1}};
  RigidRegion r;
  r.polygon.resize(3, 2);
  r.polygon << 10, 10, 20, 10, 15, 18;
  r.strength = 0.5;
  st.rigid = {r};
  const Structure back = structureFromJson(structureToJson(st), "test");
  ASSERT_EQ(back.lines.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(back.lines[k].a, st.lines[k].a);
    EXPECT_EQ(back.lines[k].b, st.lines[k].b);
    EXPECT_EQ(back.lines[k].group >= 0, st.lines[k].group >= 0);
  }
  EXPECT_EQ(back.lines[0].group, back.lines[1].group);
  ASSERT_EQ(back.rigid.size(), 1u);
  EXPECT_EQ(back.rigid[0].polygon, r.polygon);
  EXPECT_EQ(back.rigid[0].strength, 0.5);
}

TEST(StructureLines, ParallelCouplingKeepsUnityAndReproductionOnRandomProblems) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 100.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Index m = 5 + trial % 4;
    Points C(m, 2);
    for (Index i = 0; i < m; ++i) C.row(i) << u(rng), u(rng);
    Eigen::MatrixXd M(m, 3);
    M.col(0).setOnes();
    M.rightCols(2) = C;
    const Eigen::MatrixXd pinv = M * (M.transpose() * M).inverse();
    // Two nearly parallel lines (the second turned by up to 3 degrees, either orientation).
    const double angle = u(rng), turn = (u(rng) / 100.0 - 0.5) * 6.0 * std::numbers::pi / 180.0;
    StructureLine l1{Vec2(20, 30), Vec2(20, 30) + 40.0 * Vec2(std::cos(angle), std::sin(angle)), 0};
    const Vec2 d2 = (trial % 2 ? -30.0 : 30.0) * Vec2(std::cos(angle + turn), std::sin(angle + turn));
    StructureLine l2{Vec2(60, 50), Vec2(60, 50) + d2, 0};
    const std::vector<StructureLine> lines{l1, l2};
    Weights W(4, m);
    const Vec2 pts[4] = {l1.a, l1.b, l2.a, l2.b};
    for (int k = 0; k < 4; ++k) {  // weights with unity and reproduction plus a random null-space part
      Eigen::VectorXd w = pinv * Eigen::Vector3d(1.0, pts[k].x(), pts[k].y());
      Eigen::VectorXd z = Eigen::VectorXd::Random(m);
      z -= pinv * (M.transpose() * z);
      W.row(k) = (w + 0.3 * z).transpose();
    }
    const std::vector<std::array<Index, 2>> ends{{0, 1}, {2, 3}};
    coupleParallelLines(C, lines, ends, W);
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(W.row(k).sum(), 1.0, 1e-12);
      EXPECT_LE((W.row(k) * C - pts[k].transpose()).cwiseAbs().maxCoeff(), 1e-10);
    }
    if (turn == 0.0 || std::abs(turn) < 1e-15) continue;
    // Variation vectors agree up to sign except for the part that carries the lines' angle.
    const Eigen::RowVectorXd d1 = (W.row(1) - W.row(0)) / l1.length(), d2w = (W.row(3) - W.row(2)) / l2.length();
    const double s = (l1.b - l1.a).dot(l2.b - l2.a) < 0 ? -1.0 : 1.0;
    EXPECT_LE((d2w - s * d1).norm(), 2.0 * std::abs(turn) * (pinv.norm() + 1.0)) << "trial " << trial;
  }
}

TEST(StructureLines, ExactlyParallelLinesGetEqualVariationVectors) {
  Points C(4, 2);
  C << 0, 0, 100, 0, 100, 100, 0, 100;
  const std::vector<StructureLine> lines{{Vec2(20, 30), Vec2(80, 30), 0}, {Vec2(70, 60), Vec2(30, 60), 0}};
  Weights W(4, 4);
  W << 0.5, 0.2, 0.1, 0.2,  0.1, 0.6, 0.2, 0.1,  0.2, 0.3, 0.3, 0.2,  0.3, 0.1, 0.2, 0.4;
  // Make each row reproduce its point exactly first (the projection onto the affine constraints).
  Eigen::MatrixXd M(4, 3);
  M.col(0).setOnes();
  M.rightCols(2) = C;
  const Eigen::MatrixXd pinv = M * (M.transpose() * M).inverse();
  const Vec2 pts[4] = {lines[0].a, lines[0].b, lines[1].a, lines[1].b};
  for (int k = 0; k < 4; ++k) {
    const Eigen::VectorXd w = W.row(k).transpose();
    W.row(k) = (w - pinv * (M.transpose() * w - Eigen::Vector3d(1.0, pts[k].x(), pts[k].y()))).transpose();
  }
  const std::vector<std::array<Index, 2>> ends{{0, 1}, {2, 3}};
  coupleParallelLines(C, lines, ends, W);
  const Eigen::RowVectorXd d1 = (W.row(1) - W.row(0)) / 60.0, d2 = (W.row(3) - W.row(2)) / 40.0;
  EXPECT_LE((d2 + d1).cwiseAbs().maxCoeff(), 1e-14);  // opposite orientations: d2 = −d1 (5.11)
}

TEST(StructureLines, BadStructureFilesNameTheEntry) {
  const Cage cage = starCage();
  auto refused = [&](const std::string& text) { return test::structureRefusal(text, cage); };
  EXPECT_NE(refused(R"({"version": 1, "lines": [{"points": [[110, 160], [210, 165]], "parallel": "a"}]})").find("lines[0]: its parallel group"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "lines": [{"points": [[110, 160], [110, 160]]}]})").find("lines[0]: the line has zero length"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "lines": [{"points": [[110, 160], [115, 160]]}]})").find("shorter than"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "lines": [{"points": [[10, 160], [200, 160]]}]})").find("not inside the cage"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "lines": [{"points": [[110, 160], [210, 165]]}, {"points": [[160, 120], [160, 200]]}]})")
                .find("lines[1]: the line crosses lines[0]"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "lines": [{"points": [[110, 160], [210, "x"]]}]})").find("lines[0].points[1][1]"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "lines": [], "rigid": [{"polygon": [[1, 2], [30, 4], [5, 60]]}]})").find("rigid[0]: polygon point 0 is outside the cage"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "lines": [{"points": [[110, 160]]}]})").find("lines[0].points must be two points"), std::string::npos);
  EXPECT_EQ(refused(R"({"version": 1, "lines": [{"points": [[110, 160], [210, 165]]}], "rigid": []})"), "");
  BindParams lbc;
  lbc.backend = "lbc";
  Structure st = structureFromJson(R"({"version": 1, "lines": [{"points": [[110, 160], [210, 165]]}]})", "s.json");
  try {
    bind(cage, st, 320, 320, lbc);
    ADD_FAILURE() << "LBC bound lines";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lines are not supported by the 'lbc' backend (use --backend kc)"), std::string::npos) << e.what();
  }
}

TEST(StructureLines, CapabilitiesForLinesAndRigidRegionsAreSeparate) {
  Structure st;
  st.lines = {{{0, 0}, {10, 0}}};
  st.rigid = {RigidRegion{}};
  BackendCapabilities caps;
  EXPECT_EQ(unsupportedStructure(st, caps), "lines and rigid regions");
  caps.lines = true;
  EXPECT_EQ(unsupportedStructure(st, caps), "rigid regions");
  caps = {};
  caps.rigidity = true;
  EXPECT_EQ(unsupportedStructure(st, caps), "lines");
  caps.lines = true;
  EXPECT_EQ(unsupportedStructure(st, caps), "");
  EXPECT_EQ(unsupportedStructure(Structure{}, BackendCapabilities{}), "");
  EXPECT_TRUE(backendFor("kc").capabilities().lines && backendFor("kc").capabilities().rigidity);
  EXPECT_FALSE(backendFor("lbc").capabilities().lines || backendFor("lbc").capabilities().rigidity);
}

}  // namespace
}  // namespace kc::app
