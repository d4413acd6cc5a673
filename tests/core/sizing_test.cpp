// The sizing field of graded samplings: local feature size from cages, sticks and extra segments,
// the gradation bound, and the division of segments at the local spacing.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include "kc/core/sizing.h"
#include "random_point.h"

namespace kc {
namespace {

Cage polygon(std::initializer_list<std::array<double, 2>> pts) {
  Points C(static_cast<Index>(pts.size()), 2);
  Index i = 0;
  for (const auto& p : pts) C.row(i++) << p[0], p[1];
  return Cage::polygon(C);
}

/// A 200 px square with a slit `width` px wide cut 150 px deep from its top side.
Cage slit(double width) {
  const double a = 150 - width / 2, b = 150 + width / 2;
  return polygon({{50, 50}, {a, 50}, {a, 200}, {b, 200}, {b, 50}, {250, 50}, {250, 250}, {50, 250}});
}

SizingOptions options(double hMax) {
  SizingOptions o;
  o.hMax = hMax;
  o.hMin = 0.05;
  return o;
}

TEST(Sizing, CageWithoutNarrowPlaceIsUniform) {
  const SizingField h = featureSizing(polygon({{0, 0}, {100, 0}, {100, 100}, {0, 100}}), {}, options(8.0));
  EXPECT_FALSE(h.graded());
  EXPECT_EQ(h(Vec2(50, 50)), 8.0);
  EXPECT_EQ(h(Vec2(-500, 3)), 8.0);
}

TEST(Sizing, SlitGetsItsWidthOverKAndGrowsAtMostByTheGradation) {
  const SizingField h = featureSizing(slit(3.0), {}, options(10.0));
  ASSERT_TRUE(h.graded());
  // On the slit's walls lfs = 3, a gap outside the cage: h = 3/k at its seeds, every h/2 along
  // the wall, and at most a quarter of the fine gradation above it between them.
  const double wall = 3.0 / kOutsideFeatureSamples;
  EXPECT_GE(h(Vec2(148.5, 120)), wall - 1e-12);
  EXPECT_LE(h(Vec2(148.5, 120)), wall * (1.0 + 0.25 * kFineGradation) + 1e-12);
  EXPECT_NEAR(h.hMin(), 3.0 / kOutsideFeatureSamples, 1e-9);
  // Far from it, hMax.
  EXPECT_EQ(h(Vec2(60, 240)), 10.0);
  // The slit is narrower than hMax/4·4 = hMax: its walls' cones grow at the fine gradation, and
  // |h(x) − h(y)| ≤ that |x − y| on random pairs (h is a minimum of such cones).
  EXPECT_EQ(h.lipschitz(), kFineGradation);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 300);
  double steepest = 0.0;
  for (int t = 0; t < 2000; ++t) {
    const Vec2 x = test::randomPoint(u, rng), y = x + (test::randomPoint(u, rng) - Vec2(150, 150)) * 0.05;
    EXPECT_LE(std::abs(h(x) - h(y)), h.lipschitz() * (x - y).norm() + 1e-12);
    if ((x - y).norm() > 0.5) steepest = std::max(steepest, std::abs(h(x) - h(y)) / (x - y).norm());
  }
  EXPECT_GT(steepest, kSizingGradation);  // steeper than the other narrow places'
  // Beside the slit, h grows from its walls at the fine gradation: 3/4 + 0.45·d, d from the wall.
  EXPECT_NEAR(h(Vec2(148.5 - 8.0, 120)), 3.0 / kOutsideFeatureSamples + kFineGradation * 8.0, 0.05);
  // The gradient agrees with finite differences where h < hMax.
  const Vec2 x(145, 120);
  Vec2 g;
  const double v = h.valueAndGradient(x, g);
  ASSERT_LT(v, 10.0);
  const double e = 1e-6;
  EXPECT_NEAR(g.x(), (h(x + Vec2(e, 0)) - h(x - Vec2(e, 0))) / (2 * e), 1e-5);
  EXPECT_NEAR(g.y(), (h(x + Vec2(0, e)) - h(x - Vec2(0, e))) / (2 * e), 1e-5);
}

TEST(Sizing, AGapOutsideTheCageCountsOnlyWithOutsideGaps) {
  // The slit is a gap outside the cage: without outsideGaps its walls are as wide as the parts
  // they bound (97.5 px, above k·hMax), and only the slit's 3 px bottom edge refines.
  SizingOptions inner = options(10.0);
  inner.outsideGaps = false;
  const SizingField h = featureSizing(slit(3.0), {}, inner);
  EXPECT_EQ(h(Vec2(148.5, 120)), 10.0);
  EXPECT_NEAR(h(Vec2(148.5, 200)), 3.0 / kFeatureSamples, 1e-9);  // the short edge's end
  // A narrow part of the inside (a neck 3 px wide) refines either way.
  const Cage neck = polygon({{0, 0}, {100, 0}, {100, 48.5}, {200, 48.5}, {200, 0}, {300, 0}, {300, 100}, {200, 100},
                             {200, 51.5}, {100, 51.5}, {100, 100}, {0, 100}});
  const SizingField n = featureSizing(neck, {}, inner);
  EXPECT_NEAR(n(Vec2(150, 48.5)), 3.0 / kFeatureSamples, 0.05);  // seeds every h/2 along the wall
  EXPECT_NEAR(n(Vec2(150, 51.5)), 3.0 / kFeatureSamples, 0.05);
  EXPECT_EQ(n(Vec2(150, 48.5)), featureSizing(neck, {}, options(10.0))(Vec2(150, 48.5)));
}

TEST(Sizing, NarrowPlacesGetTheirWidthOverKRampingToHMaxAtTwiceIt) {
  const SizingOptions o = options(10.0);
  const double k = kFeatureSamples, rampStart = 10.0 / (1.0 - 1.0 / k);
  EXPECT_DOUBLE_EQ(narrowSpacing(4.0, o), 4.0 / k);              // w/k
  EXPECT_DOUBLE_EQ(narrowSpacing(rampStart, o), rampStart / k);  // where the ramp begins
  EXPECT_DOUBLE_EQ(narrowSpacing(16.0, o), 6.0);            // w − (n − 1)·hMax
  EXPECT_DOUBLE_EQ(narrowSpacing(20.0, o), 10.0);           // n·hMax: hMax
  EXPECT_DOUBLE_EQ(narrowSpacing(35.0, o), 10.0);
  EXPECT_DOUBLE_EQ(narrowSpacing(0.01, o), 0.05);           // hMin
  // Continuous and non-decreasing in the width, with slope at most 1.
  for (double w = 0.0; w < 30.0; w += 0.01) {
    const double a = narrowSpacing(w, o), b = narrowSpacing(w + 0.01, o);
    EXPECT_GE(b, a);
    EXPECT_LE(b - a, 0.01 + 1e-12) << w;
  }
  // The LBC mesh's k = n = 1: the width itself.
  SizingOptions lbc = o;
  lbc.featureSamples = lbc.narrowWidth = 1.0;
  EXPECT_DOUBLE_EQ(narrowSpacing(3.0, lbc), 3.0);
  EXPECT_DOUBLE_EQ(narrowSpacing(12.0, lbc), 10.0);
  // A part of the cage (a bar) narrower than n·hMax is a narrow place, on the ramp; a wider one is not.
  const SizingField ramp = featureSizing(polygon({{0, 0}, {200, 0}, {200, 19}, {0, 19}}), {}, o);
  ASSERT_TRUE(ramp.graded());
  EXPECT_DOUBLE_EQ(ramp.hMin(), 9.0);  // every seed has lfs = 19
  EXPECT_LE(ramp(Vec2(100, 0)), 9.0 + ramp.gradation() * 4.5);  // on the wall: a seed within h/2
  EXPECT_FALSE(featureSizing(polygon({{0, 0}, {200, 0}, {200, 21}, {0, 21}}), {}, o).graded());
}

TEST(Sizing, AWedgeIsANarrowPlaceDownToItsFinestSpacing) {
  // An arm meeting the torso's wall x = 180 at the armpit (180, 100) at 2.9°: at y the gap is
  // (y − 100)/20 px wide (10 px at y = 300).
  const Cage armpit = polygon({{100, 40}, {230, 40}, {226, 300}, {190, 300}, {180, 100}, {180, 320}, {100, 320}});
  const SizingOptions o = options(6.0);
  const SizingField h = featureSizing(armpit, {}, o);
  ASSERT_TRUE(h.graded());
  // On the torso's wall, 150 px below the armpit: the gap is 150 · sin θ wide, spacing width/k at
  // the seeds, which lie every half spacing along the wall (between them up to g/4 more); k of a gap
  // outside the cage.
  const double width = 150.0 * std::sin(std::atan(10.0 / 200.0)), k = kOutsideFeatureSamples;
  EXPECT_GE(h(Vec2(180, 250)), width / k * (1.0 - 0.5 * o.gradation / k));
  EXPECT_LE(h(Vec2(180, 250)), width / k * (1.0 + 0.25 * o.gradation));
  EXPECT_NEAR(h.hMin(), kWedgeFinest * o.hMax, 1e-12) << "the refinement stops towards the armpit";
  EXPECT_NEAR(h(Vec2(180, 101)), kWedgeFinest * o.hMax, 0.3);
  SizingOptions off = o;
  off.wedgeDegrees = 0.0;
  EXPECT_EQ(featureSizing(armpit, {}, off)(Vec2(180, 250)), 6.0) << "without the rule the walls share a vertex and do not count";
  // A notch of 35° cut 100 px deep into a square's top side is not a wedge; at 25° it is (15 px
  // from its bottom it is 6.3 px wide). A thin triangle's tip of 25° (inside between its walls) is not.
  const double deg = std::numbers::pi / 180.0;
  auto notch = [&](double degrees) {
    const double d = 100.0 * std::tan(0.5 * degrees * deg);
    return polygon({{0, 0}, {100 - d, 0}, {100, 100}, {100 + d, 0}, {200, 0}, {200, 200}, {0, 200}});
  };
  const Vec2 onWall = Vec2(100, 100) + 15.0 * Vec2(-std::sin(12.5 * deg), -std::cos(12.5 * deg));
  EXPECT_FALSE(featureSizing(notch(35.0), {}, o).graded());
  EXPECT_LT(featureSizing(notch(25.0), {}, o)(onWall), 6.0);
  const double y = 100.0 * std::tan(12.5 * deg);
  EXPECT_FALSE(featureSizing(polygon({{0, 0}, {100, y}, {100, -y}}), {}, o).graded());
}

TEST(Sizing, ShortEdgeRefinesItsEnds) {
  // A 2 px edge (points 1 and 2) on a 100 px shape.
  const SizingField h = featureSizing(polygon({{0, 0}, {100, 0}, {100, 49}, {100.0, 51}, {100, 100}, {0, 100}}), {}, options(8.0));
  ASSERT_TRUE(h.graded());
  EXPECT_NEAR(h(Vec2(100, 49)), 2.0 / kFeatureSamples, 1e-9);
  EXPECT_EQ(h(Vec2(10, 10)), 8.0);
}

TEST(Sizing, CrossingLinesAndALineEndingOnTheEdgeAreNotNarrow) {
  const Cage square = polygon({{0, 0}, {200, 0}, {200, 200}, {0, 200}});
  // An X of two lines crossing at the centre, and a line from the centre to the left side.
  const std::vector<FeatureSegment> x{{{60, 60}, {140, 140}}, {{60, 140}, {140, 60}}, {{0, 100}, {50, 100}}};
  const SizingField h = featureSizing(square, x, options(8.0));
  EXPECT_FALSE(h.graded()) << h.seeds().rows() << " seeds, smallest " << h.hMin();
}

// A thin rigid triangle: its sides meet only at their ends, so no pair of them is a narrow place
// (each corner was once refined to hMin through a zero-length piece where the ends met).
TEST(Sizing, ARigidTriangleWithASharpCornerIsNotNarrow) {
  const Cage square = polygon({{0, 0}, {400, 0}, {400, 400}, {0, 400}});
  const Vec2 c(100, 300), a = c + 150.0 * Vec2(std::cos(0.1745), std::sin(0.1745)), b = c + 150.0 * Vec2(std::cos(-0.1745), std::sin(-0.1745));
  const std::vector<FeatureSegment> triangle{{c, a}, {a, b}, {b, c}};
  EXPECT_FALSE(featureSizing(square, triangle, options(8.0)).graded());
}

TEST(Sizing, LineEndingNearTheEdgeIsNarrow) {
  const Cage square = polygon({{0, 0}, {200, 0}, {200, 200}, {0, 200}});
  const std::vector<FeatureSegment> line{{{1, 100}, {80, 100}}};  // 1 px from the left side
  const SizingField h = featureSizing(square, line, options(8.0));
  ASSERT_TRUE(h.graded());
  EXPECT_NEAR(h(Vec2(1, 100)), 0.25, 1e-9);
  EXPECT_NEAR(h(Vec2(0, 100)), 0.25, 0.05);  // the nearest seed on the side lies within a step
  EXPECT_EQ(h(Vec2(150, 150)), 8.0);
}

TEST(Sizing, ALineRefinesWithinFourSpacingsOfTheCageAThinPartWithinTwo) {
  // A line 16 px from the left side (hMax 6: 2.7 spacings) gets a quarter of that, 4 px; a part of
  // the cage 16 px wide (a bar) is not narrow (kNarrowWidth·hMax = 12).
  const Cage square = polygon({{0, 0}, {200, 0}, {200, 200}, {0, 200}});
  const std::vector<FeatureSegment> line{{{16, 60}, {16, 140}}};
  const SizingField h = featureSizing(square, line, options(6.0));
  ASSERT_TRUE(h.graded());
  EXPECT_NEAR(h.hMin(), 4.0, 1e-9);
  EXPECT_NEAR(h(Vec2(16, 100)), 4.0, 0.3 * 2.0);  // a seed within h/2 along the line
  EXPECT_EQ(h(Vec2(150, 100)), 6.0);
  EXPECT_FALSE(featureSizing(polygon({{0, 0}, {200, 0}, {200, 16}, {0, 16}}), {}, options(6.0)).graded());
  SizingOptions two = options(6.0);
  two.extraNarrowWidth = kNarrowWidth;  // the lines' rule as the cage's: 16 px is not narrow
  EXPECT_FALSE(featureSizing(square, line, two).graded());
}

TEST(Sizing, AGapBetweenTwoPartsIsNarrowBelowThreeSpacings) {
  // A slit 16 px wide (hMax 6: 2.7 spacings) has the outside between its walls: a quarter of its
  // width, 4 px, all along it; at 19 px (3.2 spacings) it is not narrow, nor wider. Without
  // outsideGaps (the LBC mesh) or with the inside's rule there, 16 px is not narrow either.
  const SizingField h = featureSizing(slit(16.0), {}, options(6.0));
  ASSERT_TRUE(h.graded());
  for (double y : {80.0, 120.0, 160.0}) EXPECT_NEAR(h(Vec2(142, y)), 4.0, 0.3 * 2.0) << "at y " << y;
  EXPECT_EQ(h(Vec2(100, 230)), 6.0);
  EXPECT_FALSE(featureSizing(slit(19.0), {}, options(6.0)).graded());
  EXPECT_FALSE(featureSizing(slit(26.0), {}, options(6.0)).graded());
  SizingOptions inside = options(6.0);
  inside.outsideGaps = false;
  EXPECT_FALSE(featureSizing(slit(16.0), {}, inside).graded());
  inside = options(6.0);
  inside.outsideFeatureSamples = kFeatureSamples;
  inside.outsideNarrowWidth = 1.0;
  EXPECT_FALSE(featureSizing(slit(16.0), {}, inside).graded());
  // outsideSpacing: w/k below n·hMax, hMax from there on (no ramp), hMin at the bottom.
  const SizingOptions o = options(6.0);
  EXPECT_DOUBLE_EQ(outsideSpacing(10.0, o), 10.0 / kOutsideFeatureSamples);
  EXPECT_DOUBLE_EQ(outsideSpacing(17.9, o), 17.9 / kOutsideFeatureSamples);
  EXPECT_DOUBLE_EQ(outsideSpacing(18.0, o), 6.0);
  EXPECT_DOUBLE_EQ(outsideSpacing(0.01, o), 0.05);
}

TEST(Sizing, UniformDivisionIsTheEqualOne) {
  const SizingField h = SizingField::uniform(6.0);
  const std::vector<double> t = segmentDivision(Vec2(0, 0), Vec2(100, 0), h);
  ASSERT_EQ(t.size(), 18u);  // round(100 / 6) = 17 pieces
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_EQ(t[k], static_cast<double>(k) / 17.0);
}

TEST(Sizing, GradedDivisionFollowsTheLocalSpacing) {
  const SizingField h = featureSizing(slit(3.0), {}, options(10.0));
  // The slit's wall from its bottom up to the top side: fine near... the whole wall is 3 px from the other.
  const Vec2 a(50, 50), b(50, 250);  // the left side, far from the slit: uniform
  EXPECT_EQ(segmentDivision(a, b, h).size(), 21u);
  const Vec2 c(148.5, 50), d(148.5, 200);  // a wall of the slit
  const std::vector<double> t = segmentDivision(c, d, h);
  for (std::size_t k = 1; k < t.size(); ++k) {
    const Vec2 p = c + 0.5 * (t[k] + t[k - 1]) * (d - c);
    const double step = (t[k] - t[k - 1]) * (d - c).norm();
    EXPECT_NEAR(step / h(p), 1.0, 0.2) << "at " << p.transpose();
  }
}

TEST(Sizing, SmoothProfileLiesJustBelowTheSpacingWithItsGradientBound) {
  // Around a 3 px slit and a short edge: h̃ ≤ h, h̃ ≥ 0.5·h, h̃ = hMax far away, |∇h̃| within the
  // stated bound on random points, and the gradient agrees with finite differences.
  const SizingField h = featureSizing(slit(3.0), {}, options(10.0));
  ASSERT_EQ(h.form(), SizingForm::Smooth);
  EXPECT_EQ(h.profile(Vec2(60, 240)), 10.0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 300);
  const double bound = h.lipschitz() * (1.0 + 1.875 / kSizingSoftness);
  double maxRatio = 0.0;
  for (int t = 0; t < 3000; ++t) {
    const Vec2 x = test::randomPoint(u, rng);
    Vec2 g;
    const double v = h.profile(x, &g);
    EXPECT_LE(v, h(x) + 1e-12);
    EXPECT_GE(v, 0.5 * h(x));
    EXPECT_LE(g.norm(), bound + 1e-12);
    maxRatio = std::max(maxRatio, g.norm() / h.lipschitz());
    const double e = 1e-5;
    const Vec2 fd((h.profile(x + Vec2(e, 0)) - h.profile(x - Vec2(e, 0))) / (2 * e),
                  (h.profile(x + Vec2(0, e)) - h.profile(x - Vec2(0, e))) / (2 * e));
    EXPECT_NEAR((fd - g).norm(), 0.0, 1e-5 * (1.0 + g.norm())) << x.transpose();
  }
  EXPECT_GT(maxRatio, 0.5);  // the profile does grade
  // C¹ across a ridge between two seeds: the gradient changes continuously (no jump between
  // points 1e-4 px apart anywhere on a line through the slit's refinement).
  for (double x = 120; x < 180; x += 0.01) {
    Vec2 g0, g1;
    h.profile(Vec2(x, 120), &g0);
    h.profile(Vec2(x + 1e-4, 120), &g1);
    EXPECT_LE((g1 - g0).norm(), 1e-3) << x;
  }
}

TEST(Sizing, MinProfileIsTheSpacing) {
  const SizingField s = featureSizing(slit(3.0), {}, options(10.0));
  const SizingField m(s.hMax(), s.gradation(), s.seeds(), s.sizes(), SizingForm::Min, s.slopes());
  for (double x = 100; x < 200; x += 1.7) {
    const Vec2 p(x, 130);
    EXPECT_EQ(m.profile(p), s(p));
    EXPECT_EQ(m(p), s(p));
  }
}

TEST(Sizing, RejectsBadInput) {
  EXPECT_THROW(SizingField(0.0, 0.3, Points(0, 2), Eigen::VectorXd(0)), std::invalid_argument);
  EXPECT_THROW(SizingField(5.0, 0.9, Points(0, 2), Eigen::VectorXd(0)), std::invalid_argument);
  Points P(1, 2);
  P << 0, 0;
  EXPECT_THROW(SizingField(5.0, 0.3, P, Eigen::VectorXd::Constant(1, 6.0)), std::invalid_argument);
  EXPECT_THROW(SizingField(5.0, 0.3, P, Eigen::VectorXd::Constant(1, std::nan(""))), std::invalid_argument);
  // Per-seed slopes: one per seed, each in [gradation, 0.5].
  EXPECT_THROW(SizingField(5.0, 0.3, P, Eigen::VectorXd::Constant(1, 2.0), SizingForm::Smooth, Eigen::VectorXd::Constant(2, 0.4)),
               std::invalid_argument);
  EXPECT_THROW(SizingField(5.0, 0.3, P, Eigen::VectorXd::Constant(1, 2.0), SizingForm::Smooth, Eigen::VectorXd::Constant(1, 0.2)),
               std::invalid_argument);
  EXPECT_THROW(SizingField(5.0, 0.3, P, Eigen::VectorXd::Constant(1, 2.0), SizingForm::Smooth, Eigen::VectorXd::Constant(1, 0.6)),
               std::invalid_argument);
  SizingOptions o = options(8.0);
  o.narrowWidth = 0.5;
  EXPECT_THROW(featureSizing(slit(3.0), {}, o), std::invalid_argument);
  o = options(8.0);
  o.fineGradation = 0.2;  // below the gradation
  EXPECT_THROW(featureSizing(slit(3.0), {}, o), std::invalid_argument);
}

TEST(Sizing, OnlyTheNarrowestGapsBetweenPartsGrowAtTheFineGradation) {
  // A gap between two parts narrower than hMax (w/4 below kFineSeedFraction·hMax): its seeds grow
  // at kFineGradation. A wider one (10 px at hMax 6: w/4 = 2.5), a wedge (the armpit) and a narrow
  // part of the inside (a neck) keep the gradation.
  auto slopesOf = [](const SizingField& h) {
    std::set<double> s;
    for (Index i = 0; i < h.seeds().rows(); ++i) s.insert(h.slopes().size() > 0 ? h.slopes()(i) : h.gradation());
    return s;
  };
  const SizingField narrow = featureSizing(slit(3.0), {}, options(10.0));
  EXPECT_TRUE(slopesOf(narrow).count(kFineGradation));
  // Seeds of the slit's walls are the fine ones: the wall x = 148.5 at mid-height.
  for (Index i = 0; i < narrow.seeds().rows(); ++i)
    if (std::abs(narrow.seeds()(i, 0) - 148.5) < 1e-9 && std::abs(narrow.seeds()(i, 1) - 120.0) < 5.0) {
      ASSERT_GT(narrow.slopes().size(), 0);
      EXPECT_EQ(narrow.slopes()(i), kFineGradation);
    }
  EXPECT_EQ(slopesOf(featureSizing(slit(10.0), {}, options(6.0))), std::set<double>{kSizingGradation});
  const Cage armpit = polygon({{100, 40}, {230, 40}, {226, 300}, {190, 300}, {180, 100}, {180, 320}, {100, 320}});
  const SizingField wedge = featureSizing(armpit, {}, options(6.0));
  ASSERT_TRUE(wedge.graded());
  EXPECT_EQ(slopesOf(wedge), std::set<double>{kSizingGradation});
  const Cage neck = polygon({{0, 0},
                             {100, 0},
                             {100, 48.5},
                             {200, 48.5},
                             {200, 0},
                             {300, 0},
                             {300, 100},
                             {200, 100},
                             {200, 51.5},
                             {100, 51.5},
                             {100, 100},
                             {0, 100}});
  EXPECT_EQ(slopesOf(featureSizing(neck, {}, options(10.0))), std::set<double>{kSizingGradation});
  // Off: fineGradation = gradation gives one slope.
  SizingOptions off = options(10.0);
  off.fineGradation = off.gradation;
  const SizingField plain = featureSizing(slit(3.0), {}, off);
  EXPECT_EQ(plain.slopes().size(), 0);
  EXPECT_EQ(plain.lipschitz(), kSizingGradation);
}

}  // namespace
}  // namespace kc
