// Structure lines as people draw them: two lines crossing in an X (a window frame), a line ending on
// another (a T), a line ending on or 1 px from the cage, lines beside a narrow place. A graded bind
// shares one sample where they meet and keeps them straight; a uniform bind refuses what it cannot
// resolve.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <random>

#include "kc/app/file_io.h"
#include "kc/app/line_metrics.h"
#include "kc/app/pipeline.h"
#include "kc/sampling/sampler.h"
#include "kc/core/structure/linear_along.h"
#include "kc/core/structure/lines.h"

namespace kc::app {
namespace {

Cage square(double x0, double y0, double x1, double y1) {
  Points C(4, 2);
  C << x0, y0, x1, y0, x1, y1, x0, y1;
  return Cage::polygon(C);
}

TEST(GradedLines, ContactsAreFound) {
  const std::vector<StructureLine> lines{{{60, 60}, {140, 140}}, {{60, 140}, {140, 60}}, {{100, 100}, {100, 170}},
                                         {{20, 20}, {40, 20}}, {{40, 20}, {60, 20}}};
  const std::vector<LineContact> c = lineContacts(lines);
  // 0×1 cross at (100, 100), where 2 starts (a T on both, in fact a shared point); 3 and 4 share an end.
  ASSERT_EQ(c.size(), 4u);
  for (const LineContact& x : c) {
    if (x.l == 4) {
      EXPECT_EQ(x.k, 3u);
      EXPECT_EQ(x.tk, 1.0);
      EXPECT_EQ(x.tl, 0.0);
    } else {
      EXPECT_NEAR((x.point - Vec2(100, 100)).norm(), 0.0, 1e-9);
    }
  }
  const std::vector<StructureLine> overlapping{{{0, 0}, {10, 0}}, {{5, 0}, {20, 0}}};
  EXPECT_THROW(lineContacts(overlapping), std::invalid_argument);
}

TEST(GradedLines, MeetingLinesAgreeExactlyWhereTheyMeet) {
  // Three lines crossing pairwise in a small triangle (sides 3-6 px), three through one point, and
  // an X with a line going on from one of its ends; random end weights that sum to 1 and reproduce their points.
  const std::vector<std::vector<StructureLine>> sets{
      {{{189.2, 82.9}, {214.1, 221.4}}, {{239.4, 160.3}, {108.6, 158.9}}, {{252.4, 186.9}, {161.6, 130.8}}},
      {{{50, 50}, {150, 150}}, {{50, 150}, {150, 50}}, {{100, 40}, {100, 160}}},
      {{{50, 50}, {150, 150}}, {{50, 150}, {150, 50}}, {{150, 150}, {150, 250}}}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Index m = 6;
  Points C(m, 2);
  for (Index j = 0; j < m; ++j) C.row(j) << 300.0 * u(rng), 300.0 * u(rng);
  Eigen::MatrixXd M(m, 3);
  M << Eigen::VectorXd::Ones(m), C;
  const std::size_t expectedContacts[] = {3, 3, 2};
  for (std::size_t set = 0; set < sets.size(); ++set) {
    const std::vector<StructureLine>& lines = sets[set];
    const std::vector<LineContact> contacts = lineContacts(lines);
    ASSERT_EQ(contacts.size(), expectedContacts[set]);
    // One sample per end point, shared where lines share an end (as the sampler shares it).
    std::vector<Vec2> points;
    auto sample = [&](const Vec2& p) {
      for (std::size_t i = 0; i < points.size(); ++i)
        if (points[i] == p) return Index(i);
      points.push_back(p);
      return Index(points.size() - 1);
    };
    std::vector<std::array<Index, 2>> ends;
    for (const StructureLine& l : lines) ends.push_back({sample(l.a), sample(l.b)});
    Points X(Index(points.size()), 2);
    for (std::size_t i = 0; i < points.size(); ++i) X.row(Index(i)) = points[i].transpose();
    Weights W(X.rows(), m);
    for (Index i = 0; i < X.rows(); ++i) {  // random, then the least-norm change to sum 1 and reproduce x_i
      Eigen::VectorXd r(m);
      for (Index j = 0; j < m; ++j) r(j) = u(rng);
      const Eigen::Vector3d q(1.0, X(i, 0), X(i, 1));
      W.row(i) = (r + M * (M.transpose() * M).ldlt().solve(q - M.transpose() * r)).transpose();
    }
    coupleMeetingLines(contacts, ends, W);
    for (const LineContact& c : contacts) {
      const Eigen::RowVectorXd d = (1.0 - c.tk) * W.row(ends[c.k][0]) + c.tk * W.row(ends[c.k][1]) -
                                   (1.0 - c.tl) * W.row(ends[c.l][0]) - c.tl * W.row(ends[c.l][1]);
      EXPECT_LE(d.cwiseAbs().maxCoeff(), 1e-12) << "lines " << c.k << " and " << c.l;
    }
    EXPECT_LE((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
    EXPECT_LE((W * C - X).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(GradedLines, MeetingLinesShareASampleInAGradedSampling) {
  // The sampler of a graded sampling: an X, a T from its crossing, a line ending on the cage.
  const Cage cage = square(20, 20, 280, 280);
  sampling::SamplingOptions o;
  o.spacing = 8.0;
  o.width = o.height = 300;
  o.kind = sampling::SamplerKind::BlueNoise;
  o.gradedLines = true;
  o.lines = {{{80, 80}, {220, 220}}, {{80, 220}, {220, 80}}, {{150, 150}, {150, 260}}, {{280, 240}, {200, 240}}};
  const SampleSet S = sampling::sample(cage, o);
  ASSERT_NO_THROW(S.validate(cage.size()));
  ASSERT_EQ(S.lines.size(), 4u);
  std::vector<Index> shared;
  for (Index i : S.lines[0])
    if (std::find(S.lines[1].begin(), S.lines[1].end(), i) != S.lines[1].end()) shared.push_back(i);
  ASSERT_EQ(shared.size(), 1u);
  EXPECT_EQ(S.lines[2].front(), shared[0]);
  EXPECT_NEAR((Vec2(S.X.row(shared[0])) - Vec2(150, 150)).norm(), 0.0, 1e-9);
  const Index end = S.lines[3].front();
  EXPECT_EQ(S.kind[std::size_t(end)], SampleKind::Edge);
  EXPECT_NEAR((Vec2(S.X.row(end)) - Vec2(280, 240)).norm(), 0.0, 1e-9);
}

/// Binds `lines` in `cage` at the defaults (graded) and checks they stay straight (≤ 0.1 px) under
/// 20 random ±40 px translations of every control, with unity and reproduction along them.
/// Returns the number of fit points of the lines' linear fit over the number that the largest
/// kernel width needs (Σ length / (fitSpacing·σ)).
double expectStraightGraded(const Cage& cage, const std::vector<StructureLine>& lines, int width, int height) {
  Structure st;
  st.lines = lines;
  const Session s = app::bind(cage, st, width, height, BindParams{});
  const BindReport& r = s.report;
  EXPECT_TRUE(s.params.graded);  // graded (a sizing field only where some place is narrow)
  const LineFigures f = measureLines(s, st.lines, 20, 40.0);
  std::printf("%ld samples, bind %.2f s (lines %.2f s, %ld fit points), bent %.3g px\n", long(s.samples.size()), r.timings.total,
              r.lines.seconds, long(r.lines.fitPoints), f.deviation);
  EXPECT_LE(f.deviation, 0.1);
  EXPECT_LE(f.unity, 1e-9);
  EXPECT_LE(f.reproduction, 1e-7);
  double needed = 0.0;
  for (const StructureLine& l : lines) needed += l.length() / (LinearityOptions{}.fitSpacing * s.sigma);
  return double(r.lines.fitPoints) / needed;
}

TEST(GradedLinesSlow, CrossingLinesBindAndStayStraight) {
  // An X (a window frame) and a T from its crossing: refused by a uniform bind.
  const double fitShare =
      expectStraightGraded(square(20, 20, 280, 280), {{{80, 80}, {220, 220}}, {{80, 220}, {220, 80}}, {{150, 150}, {150, 260}}},300, 300);
  // The fit is dense only near the crossing, where the width is small (0.03 px): at most 4× the
  // fit points that the largest width needs (the smallest width everywhere needed 180×).
  EXPECT_LE(fitShare, 4.0);
}

TEST(GradedLinesSlow, RandomCrossingLinesInTheStarStayStraight) {
  // The first four sets of `kcwarp-cli bench --lines --crossing` (seeds 1000 + set, the bench's
  // picture: the star's extent and 20 px): lines that pass a few px from the star's inside corners
  // and from each other between their crossings.
  const Cage star = loadCage(std::string(KC_SOURCE_DIR) + "/images/star.cage.json");
  const int w = int(std::ceil(star.C.col(0).maxCoeff() + 20.0)), h = int(std::ceil(star.C.col(1).maxCoeff() + 20.0));
  for (std::uint64_t set = 0; set < 4; ++set) {
    SCOPED_TRACE(set);
    expectStraightGraded(star, randomLines(star, 3, 100.0, 150.0, BindParams{}.spacing, 1000 + set, RandomLineLayout::Crossing), w, h);
  }
}

TEST(GradedLinesSlow, AShallowCrossingStaysStraight) {
  // Two lines crossing at 10°: 5 px from the crossing they run 0.9 px apart.
  const double t = std::tan(10.0 * std::numbers::pi / 180.0);
  expectStraightGraded(square(20, 20, 280, 280), {{{60, 150}, {240, 150}}, {{60, 150 - 90 * t}, {240, 150 + 90 * t}}}, 300, 300);
}

TEST(GradedLines, ALineEndingOnePixelFromTheEdgeStaysStraight) {
  expectStraightGraded(square(20, 20, 280, 280), {{{80, 150}, {279, 150}}},300, 300);
}

TEST(GradedLines, ALineEndingOnTheEdgeStaysStraight) {
  expectStraightGraded(square(20, 20, 280, 280), {{{280, 240}, {200, 240}}, {{80, 60}, {180, 20}}},300, 300);
}

TEST(GradedLinesSlow, LinesNearANarrowPlaceStayStraight) {
  // A slit 3 px wide with a line along each side of it, 2 px from its walls: the kernel width
  // varies along the lines (the narrow place refines it), which the smooth profile keeps kink-free.
  Points C(8, 2);
  C << 50, 50, 148.5, 50, 148.5, 200, 151.5, 200, 151.5, 50, 250, 50, 250, 250, 50, 250;
  expectStraightGraded(Cage::polygon(C), {{{146.5, 70}, {146.5, 230}}, {{153.5, 70}, {153.5, 230}}, {{60, 225}, {240, 225}}},300, 300);
}

TEST(GradedLines, EffectiveParamsAreWhatTheBindUses) {
  // A square with no narrow place, spacing 8: one line 12 px (1.5 h) from its top edge, which the
  // uniform rules accept although a graded sampling would refine between them (lfs 12 px < 2 h);
  // then the same line with two crossing lines, which they refuse.
  const Cage cage = square(20, 20, 280, 280);
  BindParams requested;
  requested.spacing = 8.0;
  requested.kc.exactLines = false;  // lines made linear through their samples
  ASSERT_TRUE(gradedSampling(requested));
  Structure beside, crossing;
  beside.lines = {{{80, 32}, {220, 32}}};
  crossing.lines = {{{80, 32}, {220, 32}}, {{80, 80}, {220, 220}}, {{80, 220}, {220, 80}}};

  const BindParams uniform = effectiveBindParams(cage, beside, requested);
  EXPECT_FALSE(gradedSampling(uniform));
  ASSERT_TRUE(bindSizing(cage, beside, requested)) << "the requested parameters would grade the sampling";
  EXPECT_FALSE(bindSizing(cage, beside, uniform));
  const Session u = app::bind(cage, beside, 300, 300, requested);
  EXPECT_FALSE(u.params.graded);
  EXPECT_FALSE(u.sizing);
  EXPECT_EQ(estimateBindCost(cage, beside, 300, 300, requested).samples, estimateBindCost(cage, beside, 300, 300, uniform).samples);
  EXPECT_NEAR(estimateBindCost(cage, beside, 300, 300, requested).samples, double(u.samples.size()), 0.25 * double(u.samples.size()));

  const BindParams graded = effectiveBindParams(cage, crossing, requested);
  EXPECT_TRUE(gradedSampling(graded));
  const auto sizing = bindSizing(cage, crossing, graded);
  ASSERT_TRUE(sizing);
  EXPECT_LT(sizing->hMin(), requested.spacing);
  const Session g = app::bind(cage, crossing, 300, 300, requested);
  EXPECT_TRUE(g.params.graded);
  ASSERT_TRUE(g.sizing);
  EXPECT_EQ(g.sizing->hMin(), sizing->hMin());
  EXPECT_EQ(g.sizing->form(), SizingForm::Smooth);  // the kernel width of a bind with lines
  // The estimate counts the refinement along the lines: within a quarter of what was sampled.
  EXPECT_NEAR(estimateBindCost(cage, crossing, 300, 300, requested).samples, double(g.samples.size()), 0.25 * double(g.samples.size()));

  // Without lines, or on a backend that meshes the cage (no lines), the parameters as given.
  EXPECT_TRUE(effectiveBindParams(cage, Structure{}, requested).graded);
  BindParams lbc = requested;
  lbc.backend = "lbc";
  EXPECT_TRUE(effectiveBindParams(cage, beside, lbc).graded);
  // Exact lines (the default) are not part of the sampling: the parameters as given, and the
  // crossing lines leave the square's one spacing.
  BindParams exact = requested;
  exact.kc.exactLines = true;
  ASSERT_TRUE(exactLines(exact));
  EXPECT_TRUE(effectiveBindParams(cage, beside, exact).graded);
  EXPECT_FALSE(bindSizing(cage, crossing, exact));
  const Session e = app::bind(cage, crossing, 300, 300, exact);
  EXPECT_FALSE(e.sizing);
  EXPECT_TRUE(e.samples.lines.empty());
}

TEST(GradedLines, UniformBindStillRefusesThem) {
  const Cage cage = square(20, 20, 280, 280);
  Structure st;
  st.lines = {{{80, 80}, {220, 220}}, {{80, 220}, {220, 80}}};
  BindParams p;
  p.graded = false;
  p.kc.exactLines = false;  // lines made linear through their samples
  try {
    app::bind(cage, st, 300, 300, p);
    FAIL() << "crossing lines bound uniformly";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("crosses lines[0]"), std::string::npos) << e.what();
  }
  // Exact lines are not sampled: a uniform bind takes them, and they stay straight.
  p.kc.exactLines = true;
  const Session s = app::bind(cage, st, 300, 300, p);
  EXPECT_FALSE(s.params.graded);
  EXPECT_LE(measureLines(s, st.lines, 10).deviation, 1e-9);
}

}  // namespace
}  // namespace kc::app
