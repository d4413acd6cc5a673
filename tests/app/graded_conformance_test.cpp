// Graded samplings in the conformance properties: cages drawn tightly (legs 4 px apart, a 3 px slit,
// a 2 px neck, a 2.9° armpit; tests/data/narrow) and random cages with a slit 1-5 px wide or a notch
// of 2-25° bind with the defaults, keep partition of unity and reproduction to round-off inside the
// cage, the Lagrange property and linear edge samples, and do not leak across their gaps.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <string>

#include "kc/app/diagnostics.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "random_point.h"

namespace kc::app {
namespace {

std::string narrowPath(const std::string& name) {
  return (std::filesystem::path(KC_SOURCE_DIR) / "tests" / "data" / "narrow" / (name + ".cage.json")).string();
}

std::pair<int, int> imageSize(const std::string& path) {
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in);
  return {j["image_size"][0].get<int>(), j["image_size"][1].get<int>()};
}

/// Binds with defaults (automatic spacing) and checks the conformance properties.
Session bindAndCheck(const Cage& cage, int w, int h, const std::string& backend = "kc") {
  BindParams p;
  p.backend = backend;
  p.spacing = automaticSpacing(cage, w, h, p);
  Session s = app::bind(cage, w, h, p);
  EXPECT_TRUE(s.hasField());
  const Diagnostics d = diagnose(s, 60000);
  EXPECT_GT(d.inside.points, 1000);
  EXPECT_LE(d.inside.partitionOfUnity, 1e-9);
  EXPECT_LE(d.inside.reproduction, 1e-7);  // pixels
  EXPECT_LE(d.lagrange, 1e-9);
  EXPECT_LT(d.samples.partitionOfUnity, 1e-12);
  for (Index i = 0; i < s.samples.size(); ++i) {
    if (s.samples.kind[std::size_t(i)] != SampleKind::Edge) continue;
    const int a = s.samples.edge(i, 0), b = s.samples.edge(i, 1);
    EXPECT_NEAR(s.W.row(i).sum() - s.W(i, a) - s.W(i, b), 0.0, 1e-12) << "edge sample " << i << " uses other controls";
  }
  return s;
}

/// max |Σ far weights| at points 1-3 px inside the cage from the vertical wall x = wall (towards
/// `inward`), y in [y0, y1]; far = the controls `isFar` selects.
template <class F>
double leak(const Session& s, double wall, double inward, double y0, double y1, F&& isFar) {
  std::vector<Vec2> pts;
  for (double d = 1.0; d <= 3.0; d += 0.5)
    for (double y = y0; y <= y1; y += 2.0) pts.emplace_back(wall + inward * d, y);
  Points P(Index(pts.size()), 2);
  for (std::size_t k = 0; k < pts.size(); ++k) P.row(Index(k)) = pts[k].transpose();
  const Weights W = s.field->weightsAt(P);
  double worst = 0.0;
  for (Index k = 0; k < P.rows(); ++k) {
    double sum = 0.0;
    for (Index i = 0; i < s.cage.size(); ++i)
      if (isFar(Vec2(s.cage.C.row(i)))) sum += W(k, i);
    worst = std::max(worst, std::abs(sum));
  }
  return worst;
}

TEST(GradedConformance, TightlyDrawnCagesBindAndHoldTheProperties) {
  for (const char* name : {"person-narrow", "slit-narrow", "neck-narrow"}) {
    SCOPED_TRACE(name);
    const Cage cage = loadCage(narrowPath(name));
    const auto [w, h] = imageSize(narrowPath(name));
    const Session s = bindAndCheck(cage, w, h);
    ASSERT_TRUE(s.sizing) << "a cage with a narrow place samples graded";
    EXPECT_LT(s.sizing->hMin(), 0.5 * s.params.spacing);
  }
}

TEST(GradedConformance, NoLeakAcrossAGap) {
  {
    // The person's legs, 4 px apart: 1-3 px inside the right leg, its lower half, the left leg's
    // lower controls (geodesically 150+ px away) weigh at most 0.02 together.
    const Cage cage = loadCage(narrowPath("person-narrow"));
    const auto [w, h] = imageSize(narrowPath("person-narrow"));
    BindParams p;
    p.spacing = automaticSpacing(cage, w, h, p);
    const Session s = app::bind(cage, w, h, p);
    const double l = leak(s, 202.0, 1.0, 400.0, 460.0, [](const Vec2& c) { return c.x() < 200.0 && c.y() > 400.0; });
    std::printf("[measured] person legs: leak %.4f\n", l);
    EXPECT_LE(l, 0.02);
  }
  {
    // The slit, 3 px: inside its left wall near the top, the controls right of the slit's top (280 px round).
    const Cage cage = loadCage(narrowPath("slit-narrow"));
    BindParams p;
    p.spacing = automaticSpacing(cage, 300, 300, p);
    const Session s = app::bind(cage, 300, 300, p);
    const double l = leak(s, 148.5, -1.0, 55.0, 120.0, [](const Vec2& c) { return c.x() > 150.0 && c.y() < 60.0; });
    std::printf("[measured] slit: leak %.4f\n", l);
    EXPECT_LE(l, 0.02);
  }
}

TEST(GradedConformance, NoLeakAcrossAGapOfAnyWidth) {
  // Slits 6-20 px wide cut 150 px deep into a 200 px square, at hMax = 6 (1-3.3 spacings: gaps a
  // uniform sampling held with one to three samples across): 1-3 px inside the left wall, all along
  // the slit, the controls right of its top (250+ px round it) weigh at most 0.02 together.
  for (double width : {6.0, 10.0, 14.0, 20.0}) {
    SCOPED_TRACE(width);
    const double a = 150.0 - width / 2.0, b = 150.0 + width / 2.0;
    Points C(8, 2);
    C << 50, 50, a, 50, a, 200, b, 200, b, 50, 250, 50, 250, 250, 50, 250;
    BindParams p;
    p.spacing = 6.0;
    const Session s = app::bind(Cage::polygon(C), 300, 300, p);
    const double l = leak(s, a, -1.0, 55.0, 195.0, [](const Vec2& c) { return c.x() > 150.0 && c.y() < 60.0; });
    std::printf("[measured] slit %.0f px at h 6: leak %.4f\n", width, l);
    EXPECT_LE(l, 0.02);
  }
}

TEST(GradedConformance, ThePlainInterpolationBlendsOnlyTheGapsItRefined) {
  // `--interp thesis` refines a gap between two parts only below 2·hMax (the exact form: 3·hMax).
  // A 14 or 16 px slit at hMax = 6 is then sampled as it is, and its exterior rows must not blend
  // its two walls, which they did when the blend's width limit was the exact form's (far side's
  // weight up to 0.077 1-3 px inside the wall; 0.025-0.034 continuing the nearer wall). A 3 px slit
  // beside it makes the sampling graded.
  for (const double width : {14.0, 16.0})
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      SCOPED_TRACE(testing::Message() << width << " px, seed " << seed);
      const double a = 130.0 - width / 2.0, b = 130.0 + width / 2.0;
      Points C(12, 2);
      C << 50, 50, a, 50, a, 200, b, 200, b, 50, 220, 50, 220, 150, 223, 150, 223, 50, 250, 50, 250, 250, 50, 250;
      BindParams p;
      p.spacing = 6.0;
      p.seed = seed;
      p.kc.interp = InterpMode::Thesis;
      const Session s = app::bind(Cage::polygon(C), 300, 300, p);
      ASSERT_TRUE(s.sizing);
      const double l = leak(s, a, -1.0, 55.0, 195.0, [&](const Vec2& c) { return c.x() > 130.0 && c.y() < 60.0; });
      std::printf("[measured] thesis, slit %.0f px at h 6, seed %d: leak %.4f\n", width, int(seed), l);
      EXPECT_LE(l, 0.04);
    }
}

TEST(GradedConformance, NoLeakAcrossAWedge) {
  // An arm drawn close to the body: its inner wall meets the torso's at the armpit at 2.9°, a gap
  // 0-10 px wide whose walls share the armpit's vertex. 1-3 px inside the torso, from 10 px below
  // the armpit to 30 px above the wedge's mouth, the arm's lower controls (geodesically 200+ px
  // away) weigh at most 0.02 together.
  const Cage cage = loadCage(narrowPath("armpit-narrow"));
  const auto [w, h] = imageSize(narrowPath("armpit-narrow"));
  const Session s = bindAndCheck(cage, w, h);
  ASSERT_TRUE(s.sizing);
  const double l = leak(s, 180.0, -1.0, 110.0, 270.0, [](const Vec2& c) { return c.x() > 185.0 && c.y() > 250.0; });
  std::printf("[measured] armpit wedge: leak %.4f\n", l);
  EXPECT_LE(l, 0.02);
}

/// A random star-shaped cage of 7-13 points round (200, 200) whose edge 0 → 1 (a, b) is cut by a
/// notch: a, notch(mid, along, in, depth)…, b, with mid the edge's middle, along its direction, in
/// the direction from mid to the centre and depth 60% of that distance.
template <class Notch>
Cage randomNotchedCage(std::mt19937_64& rng, Notch&& notch) {
  std::uniform_real_distribution<double> radius(110.0, 170.0);
  std::uniform_int_distribution<int> count(7, 13);
  const int m = count(rng);
  std::vector<Vec2> p;
  for (int i = 0; i < m; ++i) {
    const double t = 2.0 * std::numbers::pi * i / m;
    const Vec2 r = test::randomPoint(radius, rng);  // a radius for each coordinate
    p.emplace_back(200.0 + r.x() * std::cos(t), 200.0 + r.y() * std::sin(t));
  }
  const Vec2 a = p[0], b = p[1], mid = 0.5 * (a + b), centre(200, 200);
  const std::vector<Vec2> cut = notch(mid, (b - a).normalized(), (centre - mid).normalized(), 0.6 * (centre - mid).norm());
  std::vector<Vec2> q{a};
  q.insert(q.end(), cut.begin(), cut.end());
  q.insert(q.end(), p.begin() + 1, p.end());
  Points C(Index(q.size()), 2);
  for (std::size_t k = 0; k < q.size(); ++k) C.row(Index(k)) = q[k].transpose();
  return Cage::polygon(C);
}

/// randomNotchedCage with a radial slit `width` px wide.
Cage randomSlitCage(std::mt19937_64& rng, double width) {
  return randomNotchedCage(rng, [&](const Vec2& mid, const Vec2& along, const Vec2& in, double depth) {
    const Vec2 l0 = mid - 0.5 * width * along, r0 = mid + 0.5 * width * along;
    return std::vector<Vec2>{l0, l0 + depth * in, r0 + depth * in, r0};
  });
}

TEST(GradedConformance, RandomCagesWithASlitBind) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> width(1.0, 5.0);
  for (int trial = 0; trial < 4; ++trial) {
    const double wd = width(rng);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", slit " + std::to_string(wd) + " px");
    const Cage cage = randomSlitCage(rng, wd);
    ASSERT_NO_THROW(validateCage(cage));
    const Session s = bindAndCheck(cage, 400, 400);
    ASSERT_TRUE(s.sizing);
    EXPECT_NEAR(s.sizing->hMin(), wd / kFeatureSamples, 0.2 * wd);
  }
}

/// randomNotchedCage with a V-shaped notch of `degrees`: a wedge whose walls meet at its tip.
/// `wall`, `tip`: the notch's first wall's mouth end and its tip.
Cage randomWedgeCage(std::mt19937_64& rng, double degrees, Vec2& wall, Vec2& tip) {
  return randomNotchedCage(rng, [&](const Vec2& mid, const Vec2& along, const Vec2& in, double depth) {
    const double half = depth * std::tan(0.5 * degrees * std::numbers::pi / 180.0);
    tip = mid + depth * in;
    wall = mid - half * along;
    return std::vector<Vec2>{wall, tip, mid + half * along};
  });
}

TEST(GradedConformance, RandomCagesWithAWedgeDoNotLeakAcrossIt) {
  // Beside the first wall of the notch, 1-3 px inside the cage where the notch is a narrow place
  // (narrower than two spacings) and 10 px or more from its tip, the other wall's mouth corner and the
  // control after it (geodesically round the tip) weigh at most 0.02 together.
  std::mt19937_64 rng(2027);
  std::uniform_real_distribution<double> angle(2.0, 25.0);
  for (int trial = 0; trial < 4; ++trial) {
    const double degrees = angle(rng);
    Vec2 wall, tip;
    const Cage cage = randomWedgeCage(rng, degrees, wall, tip);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", wedge " + std::to_string(degrees) + " degrees");
    ASSERT_NO_THROW(validateCage(cage));
    const Session s = bindAndCheck(cage, 400, 400);
    const Vec2 along = (tip - wall).normalized();
    Vec2 out(-along.y(), along.x());  // the wall's normal away from the notch
    if ((0.5 * (wall + tip) + out - tip).norm() < (0.5 * (wall + tip) - out - tip).norm()) out = -out;
    const CageQueries inside(cage);
    if (!inside.inside(0.5 * (wall + tip) + 2.0 * out)) out = -out;
    std::vector<Vec2> pts;
    const double length = (tip - wall).norm();
    const double mouth = (Vec2(cage.C.row(3)) - wall).norm();  // the notch's width at its mouth
    for (double f = 0.0; f <= 1.0; f += 0.01) {
      const double width = mouth * (1.0 - f);
      if (width > s.params.spacing || (1.0 - f) * length < 10.0) continue;  // narrower than a spacing, 10 px from the tip
      for (double d = 1.0; d <= 3.0; d += 0.5) pts.push_back(wall + f * length * along + d * out);
    }
    ASSERT_GT(pts.size(), 50u);
    Points P(Index(pts.size()), 2);
    for (std::size_t k = 0; k < pts.size(); ++k) P.row(Index(k)) = pts[k].transpose();
    const Weights W = s.field->weightsAt(P);
    double worst = 0.0;
    for (Index k = 0; k < P.rows(); ++k) worst = std::max(worst, std::abs(W(k, 3) + W(k, 4)));  // the other wall's mouth and the next control
    std::printf("[measured] wedge %.1f degrees: leak %.4f, %ld samples\n", degrees, worst, long(s.samples.size()));
    EXPECT_LE(worst, 0.02);
  }
}

TEST(GradedConformance, UniformSpacingStillRefusesNarrowPlaces) {
  // --uniform-spacing keeps the old rule: a gap narrower than the spacing is refused, naming it.
  const Cage cage = loadCage(narrowPath("slit-narrow"));
  BindParams p;
  p.graded = false;
  p.spacing = 6.0;
  try {
    app::bind(cage, 300, 300, p);
    FAIL() << "a 3 px slit at spacing 6 binds uniformly";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("3 px apart"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace kc::app

namespace kc::app {
namespace {

TEST(GradedConformance, SessionsKeepTheWidthProfile) {
  // A graded session with a line round-trips with its smooth profile and evaluates identically; the same
  // sizing block without "form" (a session written before the smooth profile) loads the min form.
  Points C(8, 2);
  C << 50, 50, 148.5, 50, 148.5, 200, 151.5, 200, 151.5, 50, 250, 50, 250, 250, 50, 250;
  EXPECT_EQ(app::bind(Cage::polygon(C), 300, 300, BindParams{}).sizing->form(), SizingForm::Min);  // no lines
  Structure st;
  st.lines = {{{120.0, 70}, {120.0, 230}}};
  EXPECT_EQ(app::bind(Cage::polygon(C), st, 300, 300, BindParams{}).sizing->form(), SizingForm::Min);  // exact lines: not sampled
  BindParams sampled;  // lines made linear through their samples (sessions written before the exact correction)
  sampled.kc.exactLines = false;
  const Session s = app::bind(Cage::polygon(C), st, 300, 300, sampled);
  ASSERT_TRUE(s.sizing);
  EXPECT_EQ(s.sizing->form(), SizingForm::Smooth);
  const std::string text = sessionToJson(s);
  const Session t = sessionFromJson(text, "graded.kcw.json");
  ASSERT_TRUE(t.sizing);
  EXPECT_EQ(t.sizing->form(), SizingForm::Smooth);
  EXPECT_LT(t.sizing->profile(Vec2(147.0, 120.0)), (*t.sizing)(Vec2(147.0, 120.0))) << "the smooth profile lies below h there";
  Points P(3, 2);
  P << 147.0, 120.0, 153.0, 60.0, 100.0, 220.0;
  EXPECT_EQ(s.field->weightsAt(P), t.field->weightsAt(P));
  // The slit's walls grow at the fine gradation: their seeds' slopes round-trip (a 4th entry).
  ASSERT_GT(s.sizing->slopes().size(), 0);
  EXPECT_EQ(s.sizing->lipschitz(), kFineGradation);
  EXPECT_EQ(t.sizing->slopes(), s.sizing->slopes());
  nlohmann::json j = nlohmann::json::parse(text);
  {
    nlohmann::json bad = j;
    for (auto& seed : bad["sizing"]["seeds"])
      if (seed.size() == 4) {
        seed[3] = 0.7;  // steeper than any cone may be
        break;
      }
    try {
      (void)sessionFromJson(bad.dump(), "slope.kcw.json");
      ADD_FAILURE() << "a seed slope of 0.7 loaded";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find("slope.kcw.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("slopes must be in [gradation, 0.5]"), std::string::npos) << e.what();
    }
    nlohmann::json plain = j;  // a session written before per-seed slopes: every cone at the gradation
    for (auto& seed : plain["sizing"]["seeds"])
      if (seed.size() == 4) seed.erase(3);
    plain.erase("field");
    const Session before = sessionFromJson(plain.dump(), "before.kcw.json");
    EXPECT_EQ(before.sizing->slopes().size(), 0);
    EXPECT_EQ(before.sizing->lipschitz(), before.sizing->gradation());
  }
  j["sizing"].erase("form");
  j.erase("field");  // re-solved from the samples and weights with the min-form width
  const Session old = sessionFromJson(j.dump(), "old.kcw.json");
  ASSERT_TRUE(old.sizing);
  EXPECT_EQ(old.sizing->form(), SizingForm::Min);
  EXPECT_EQ(old.sizing->profile(Vec2(147.0, 120.0)), (*old.sizing)(Vec2(147.0, 120.0)));
  j["sizing"]["form"] = "wavy";
  EXPECT_THROW(sessionFromJson(j.dump(), "bad.kcw.json"), std::exception);
}

}  // namespace
}  // namespace kc::app
