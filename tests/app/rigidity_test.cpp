// Rigid regions in sessions (thesis 5.4, docs/rigidity.md): structure files, bind,
// session files, the brush entry point (app::setRigidity) and the Fig 6.37 quality goals.

#include "kc/app/rigidity.h"

#include <gtest/gtest.h>

#include "structure_refusal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/app/structure.h"

namespace kc::app {
namespace {

const std::string kImages = std::string(KC_SOURCE_DIR) + "/images";

Session bindStar(const Structure& st = {}) {
  const Cage cage = loadCage(kImages + "/star.cage.json");
  return bind(cage, st, 320, 320, frameBindParams());  // the thesis's set-up: weights over the whole picture
}

/// Points of a grid of spacing `step` over the session's image farther than 6σ from every sample with ρ > 0.
Points farFrom(const Session& s, const std::vector<double>& rho, double step) {
  Points P(0, 2);
  for (double y = 2.0; y < s.imageHeight; y += step)
    for (double x = 2.0; x < s.imageWidth; x += step) {
      bool far = true;
      for (Index i = 0; i < s.samples.size() && far; ++i)
        far = rho[std::size_t(i)] == 0.0 || (s.samples.X.row(i).transpose() - Vec2(x, y)).norm() > 6.0 * s.sigma;
      if (!far) continue;
      P.conservativeResize(P.rows() + 1, 2);
      P.row(P.rows() - 1) << x, y;
    }
  return P;
}

TEST(RigidRegionsApp, Fig637SetUpKeepsPropertiesAndFarWeights) {
  Session plain = bindStar();
  const StarLegSetup leg = starLegSetup(plain.cage);
  const RigidityFigures none = measureRigidity(plain, leg.polygon, leg.pose);
  Session s = sessionFromJson(sessionToJson(plain), "copy");
  const RigidRegion region{leg.polygon, 1.0};
  const std::vector<double> rho = rigidityOfRegions(s.samples.X, std::span(&region, 1));
  const RigidityUpdate u = setRigidity(s, rho);
  const RigidityFigures f = measureRigidity(s, leg.polygon, leg.pose);
  std::printf("mean |J-R|: %.4f without rigidity, %.4f with (energy %.4g -> %.4g, %d solver rounds)\n", none.distortion,
              f.distortion, u.report.energyBefore, u.report.energyAfter, u.report.solver.iterations);
  // The goal: at most half the distortion without rigidity (measured 0.2708 -> 0.1304, docs/rigidity.md).
  EXPECT_LE(f.distortion, 0.5 * none.distortion);
  EXPECT_GT(u.report.region, 20);
  EXPECT_TRUE(u.report.solver.converged);
  EXPECT_LT(u.report.energyAfter, 0.9 * u.report.energyBefore);
  EXPECT_GE(u.report.minWeight, -1e-7);
  EXPECT_LE(f.unity, 1e-9);
  EXPECT_LE(f.reproduction, 1e-9);
  // Weights farther than 6σ from the region's samples: unchanged.
  const Points P = farFrom(s, rho, 6.0);
  ASSERT_GT(P.rows(), 1000);
  EXPECT_LE((s.field->weightsAt(P) - plain.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-4);
  // Lagrange at the controls is kept.
  EXPECT_LE((s.field->weightsAt(s.cage.C) - Weights::Identity(10, 10)).cwiseAbs().maxCoeff(), 1e-9);

  // Saved and reloaded: the same polygons, ρ and field.
  s.structure.rigid = {region};
  const Session back = sessionFromJson(sessionToJson(s), "back");
  ASSERT_EQ(back.structure.rigid.size(), 1u);
  EXPECT_TRUE(back.structure.rigid[0].polygon == leg.polygon);
  EXPECT_EQ(back.rigidity, s.rigidity);
  EXPECT_LE((back.field->weightsAt(P) - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);

  // Rigidity off again: the unconstrained weights come back.
  const RigidityUpdate off = setRigidity(s, std::vector<double>(rho.size(), 0.0));
  EXPECT_FALSE(off.rows.empty());
  EXPECT_LE((s.W - plain.W).cwiseAbs().maxCoeff(), 1e-12);
}

// The figure's rigid octagon from its structure file, without the lines: a graded bind samples it
// at the spacing of the plain bind. Its sides meet only at their ends, so no corner is a narrow
// place (each corner was refined to the smallest spacing once, and the rigidity QP went dense).
TEST(RigidRegionsApp, ARigidPolygonDoesNotRefineItsCorners) {
  const Cage cage = loadCage(kImages + "/figure.cage.json");
  Structure st = loadStructure(kImages + "/figure.structure.json");
  st.lines.clear();
  ASSERT_EQ(st.rigid.size(), 1u);
  const Session plain = bind(cage, 320, 400, BindParams{}), rigid = bind(cage, st, 320, 400, BindParams{});
  std::printf("%ld samples without the octagon, %ld with; smallest spacing %.3g px\n", long(plain.samples.size()),
              long(rigid.samples.size()), rigid.sizing ? rigid.sizing->hMin() : rigid.params.spacing);
  EXPECT_LE(rigid.samples.size(), plain.samples.size() + plain.samples.size() / 10);
  if (rigid.sizing) {
    EXPECT_GE(rigid.sizing->hMin(), 0.25 * rigid.params.spacing);
  }
}

TEST(RigidRegionsApp, ProgressAndCancel) {
  const Session plain = bindStar();
  const StarLegSetup leg = starLegSetup(plain.cage);
  const RigidRegion region{leg.polygon, 1.0};
  const std::vector<double> rho = rigidityOfRegions(plain.samples.X, std::span(&region, 1));
  // Progress: stages in order, fractions non-decreasing in [0, 1], the solver's rounds among them.
  Session s = sessionFromJson(sessionToJson(plain), "copy");
  std::vector<double> seen;
  int solving = 0;
  setRigidity(s, rho, [&](const char* stage, double f) {
    seen.push_back(f);
    solving += std::string(stage) == "rigidity solve";
    return true;
  });
  ASSERT_GE(seen.size(), 4u);
  EXPECT_GE(solving, 2);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_GE(seen.front(), 0.0);
  EXPECT_LE(seen.back(), 1.0);
  // Cancelled in the middle of the solve: the session is as it was (weights, ρ, field).
  for (int stopAt : {1, 3}) {
    Session c = sessionFromJson(sessionToJson(plain), "copy");
    int calls = 0;
    EXPECT_THROW(setRigidity(c, rho, [&](const char*, double) { return ++calls < stopAt; }), Cancelled);
    EXPECT_EQ(calls, stopAt);
    EXPECT_EQ(c.W, plain.W);
    EXPECT_EQ(c.rigidity, plain.rigidity);
    EXPECT_LE((c.field->weightsAt(leg.polygon) - plain.field->weightsAt(leg.polygon)).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(RigidRegionsApp, BindWithAStructureFileAndBadEntries) {
  const Cage cage = loadCage(kImages + "/star.cage.json");
  auto refused = [&](const std::string& text) { return test::structureRefusal(text, cage); };
  EXPECT_NE(refused(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [170, 150]]}]})").find("s.json: rigid[0].polygon must be at least 3 points"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [170, 150], [160, 170]], "strength": 1.5}]})").find("rigid[0].strength"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [170, 150], [160, 170]], "strength": "x"}]})").find("rigid[0].strength"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [170, 150], [160, 170]]}, {"polygon": [[0, 0], [10, 0], [5, 5]]}]})").find("rigid[1]: polygon point 0 is outside the cage"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [180, 180], [180, 150], [150, 160]]}]})").find("rigid[0]: the polygon intersects itself"), std::string::npos);
  EXPECT_NE(refused(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [170, "n"], [160, 170]]}]})").find("rigid[0].polygon"), std::string::npos);
  const Structure st = structureFromJson(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [170, 150], [160, 170]], "strength": 0.5}]})", "s.json");
  EXPECT_EQ(refused(R"({"version": 1, "rigid": [{"polygon": [[150, 150], [170, 150], [160, 170]], "strength": 0.5}]})"), "");
  const Session s = bind(cage, st, 320, 320, BindParams{});
  EXPECT_GT(std::count_if(s.rigidity.begin(), s.rigidity.end(), [](double r) { return r == 0.5; }), 3);
  BindParams lbc;
  lbc.backend = "lbc";
  try {
    bind(cage, st, 320, 320, lbc);
    ADD_FAILURE() << "LBC bound rigid regions";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rigid regions are not supported by the 'lbc' backend"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace kc::app

namespace kc::app {
namespace {

/// A brush stroke as the GUI's rigidity brush paints it (ui/src/tools/rigidity_tool.cpp): dabs
/// along a segment every radius/4, ρ = strength · max over dabs of the falloff (1 inside
/// (1 − softness)·radius, then (1 − t²)² to 0 at the radius), on interior and line samples,
/// values below 1e-3 dropped.
std::vector<double> brushStroke(const Session& s, const Vec2& from, const Vec2& to, double radius, double softness, double strength) {
  std::vector<double> rho(std::size_t(s.samples.size()), 0.0);
  const int dabs = std::max(1, int(std::ceil((to - from).norm() / (0.25 * radius))));
  for (int d = 0; d <= dabs; ++d) {
    const Vec2 c = from + (to - from) * (double(d) / dabs);
    for (Index i = 0; i < s.samples.size(); ++i) {
      const SampleKind k = s.samples.kind[std::size_t(i)];
      if (k != SampleKind::Interior && k != SampleKind::Line) continue;
      const double dist = (s.samples.X.row(i).transpose() - c).norm(), core = (1.0 - softness) * radius;
      if (dist >= radius) continue;
      const double t = dist <= core ? 0.0 : (dist - core) / (softness * radius), q = 1.0 - t * t;
      const double r = strength * q * q;
      if (r >= 1e-3) rho[std::size_t(i)] = std::max(rho[std::size_t(i)], r);
    }
  }
  return rho;
}

/// A photo's cage (29 points around a football player in a 548×342 picture, the GUI's default bind).
Cage playerCage() {
  const double pts[29][2] = {{62, 84},   {100, 88},  {160, 108}, {205, 90},  {215, 62},  {245, 55},  {268, 80},  {300, 110},
                             {345, 140}, {382, 158}, {372, 184}, {305, 160}, {300, 205}, {350, 228}, {420, 250}, {462, 270},
                             {448, 295}, {372, 268}, {335, 278}, {285, 285}, {310, 318}, {310, 335}, {250, 336}, {240, 290},
                             {222, 255}, {208, 232}, {176, 186}, {146, 137}, {95, 102}};
  Points C(29, 2);
  for (int i = 0; i < 29; ++i) C.row(i) << pts[i][0], pts[i][1];
  return Cage::polygon(C);
}

// A GUI stroke of the rigidity brush (radius 25, softness 0.5, strength 1) down a photo's torso
// took 39 s from release to picture: the primal-dual active set cycled on the soft ρ's degenerate
// bounds for 50 rounds (1,282 → ~1,600 active pairs) and the ADMM fallback needed 2,647
// iterations. The solver must settle by itself in a bounded number of rounds.
TEST(RigidRegionsAppSlow, SoftBrushStrokeOnAPhotoCage) {
  const Session plain = bind(playerCage(), 548, 342, frameBindParams());  // weights compared over the whole picture
  Session s = sessionFromJson(sessionToJson(plain), "copy");
  const std::vector<double> rho = brushStroke(s, Vec2(252, 135), Vec2(252, 212), 25.0, 0.5, 1.0);
  const RigidityUpdate u = setRigidity(s, rho);
  std::printf("region %ld nodes %ld controls %ld held %ld: %s %d rounds, converged %d, %.3f s (QP %.3f s)\n", long(u.report.region),
              long(u.report.nodes), long(u.report.controls), long(u.report.held),
              u.report.solver.method == RigidityQpMethod::ActiveSet ? "active set" : "ADMM", u.report.solver.iterations,
              int(u.report.solver.converged), u.seconds, u.report.solver.seconds);
  EXPECT_GT(u.report.region, 120);
  EXPECT_GT(std::count_if(rho.begin(), rho.end(), [](double r) { return r > 0.0 && r < 1.0; }), 30);  // soft: partial ρ
  EXPECT_EQ(u.report.solver.method, RigidityQpMethod::ActiveSet);
  EXPECT_TRUE(u.report.solver.converged);
  EXPECT_LE(u.report.solver.iterations, 100);
  EXPECT_LT(u.report.energyAfter, u.report.energyBefore);
  EXPECT_GE(u.report.minWeight, -1e-7);
  Points core(4, 2);
  core << 240, 125, 264, 125, 264, 222, 240, 222;
  const RigidityFigures f = measureRigidity(s, core, restPose(29), 2.0);
  EXPECT_LE(f.unity, 1e-9);
  EXPECT_LE(f.reproduction, 1e-9);
  const Points P = farFrom(s, rho, 8.0);
  ASSERT_GT(P.rows(), 1000);
  EXPECT_LE((s.field->weightsAt(P) - plain.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-4);
}

}  // namespace
}  // namespace kc::app
