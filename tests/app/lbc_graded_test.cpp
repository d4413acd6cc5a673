// The LBC backend on cages with narrow places (tests/data/narrow): every one binds at the
// defaults (automatic mesh spacing, graded mesh), with exact barycentric weights inside the cage
// and no weight across a gap.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/core/field/mesh_field.h"
#include "kc/core/lbc/cage_mesh.h"
#include "random_point.h"

namespace kc::app {
namespace {

const std::string kNarrow = std::string(KC_SOURCE_DIR) + "/tests/data/narrow/";

struct Bound {
  Session session;
  double spacing = 0.0;
};

/// The cage `name` bound by the LBC backend as the CLI does without --spacing.
const Bound& boundLbc(const std::string& name) {
  static std::map<std::string, Bound> cache;
  if (auto it = cache.find(name); it != cache.end()) return it->second;
  const std::string path = kNarrow + name + ".cage.json";
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
  const int w = j["image_size"][0], h = j["image_size"][1];
  const Cage cage = loadCage(path);
  BindParams p;
  p.backend = "lbc";
  p.spacing = automaticSpacing(cage, w, h, p);
  Bound b{bind(cage, w, h, p), p.spacing};
  return cache.emplace(name, std::move(b)).first->second;
}

/// Random points inside the cage (rejection sampling in its bounding box).
Points pointsInside(const Cage& cage, int count, unsigned seed) {
  std::mt19937 rng(seed);
  const Vec2 lo = cage.C.colwise().minCoeff(), hi = cage.C.colwise().maxCoeff();
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  std::vector<Vec2> got;
  while (int(got.size()) < count)
    if (const Vec2 x = test::randomPoint(ux, uy, rng); insideCage(cage, x)) got.push_back(x);
  Points P(count, 2);
  for (int i = 0; i < count; ++i) P.row(i) = got[std::size_t(i)];
  return P;
}

/// The checks of one narrow cage bound at the defaults.
void checkBoundAtDefaults(const std::string& name) {
  const Bound& b = boundLbc(name);
  const Session& s = b.session;
  ASSERT_TRUE(s.hasField());
  EXPECT_GE(b.spacing, BindParams{}.spacing);
  // The narrow cages mesh graded, finer than the spacing at their narrow places: every triangle's
  // longest edge within min(spacing, h(centroid)).
  if (name.find("-narrow") != std::string::npos) {
    ASSERT_TRUE(s.sizing);
    EXPECT_LT(s.sizing->hMin(), 0.5 * b.spacing);
    const auto* mesh = dynamic_cast<const MeshField*>(s.field.get());
    ASSERT_NE(mesh, nullptr);
    const Points& V = mesh->vertices();
    double worst = 0.0, finest = b.spacing;
    for (const auto& t : mesh->triangles()) {
      const Vec2 a = V.row(t[0]), c = V.row(t[1]), d = V.row(t[2]);
      const double longest = std::max({(a - c).norm(), (c - d).norm(), (d - a).norm()});
      worst = std::max(worst, longest / std::min(b.spacing, (*s.sizing)((a + c + d) / 3.0)));
      finest = std::min(finest, longest);
    }
    EXPECT_LE(worst, 1.0 + 1e-9);
    EXPECT_LT(finest, 0.5 * b.spacing);
  }
  const Points P = pointsInside(s.cage, 2000, 7);
  const Weights W = s.field->weightsAt(P);
  double unity = 0.0, reproduction = 0.0;
  for (Index i = 0; i < P.rows(); ++i) {
    unity = std::max(unity, std::abs(W.row(i).sum() - 1.0));
    reproduction = std::max(reproduction, (W.row(i) * s.cage.C - P.row(i)).norm());
    ASSERT_GE(W.row(i).minCoeff(), 0.0) << "point " << i;
  }
  EXPECT_LE(unity, 1e-9);
  EXPECT_LE(reproduction, 1e-7);
}

std::string testName(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = info.param;
  std::replace(n.begin(), n.end(), '-', '_');
  return n;
}

class LbcNarrowCage : public ::testing::TestWithParam<std::string> {};
TEST_P(LbcNarrowCage, BindsAtTheDefaultsWithExactBarycentricWeightsInside) { checkBoundAtDefaults(GetParam()); }
INSTANTIATE_TEST_SUITE_P(Narrow, LbcNarrowCage, ::testing::Values("slit-narrow", "slit-wide", "neck-narrow", "neck-wide"), testName);

// The person cages take 4-20 s each to bind (ADMM iterations on 31 controls).
class LbcNarrowCageSlow : public ::testing::TestWithParam<std::string> {};
TEST_P(LbcNarrowCageSlow, BindsAtTheDefaultsWithExactBarycentricWeightsInside) { checkBoundAtDefaults(GetParam()); }
INSTANTIATE_TEST_SUITE_P(Narrow, LbcNarrowCageSlow, ::testing::Values("person-narrow", "person-wide"), testName);

TEST(LbcNarrowCage, AGradedSessionRoundTripsWithItsSizingField) {
  const Session& s = boundLbc("slit-narrow").session;
  const Session back = sessionFromJson(sessionToJson(s), "slit");
  ASSERT_TRUE(back.sizing);
  EXPECT_EQ(back.sizing->seeds(), s.sizing->seeds());
  EXPECT_EQ(back.sizing->sizes(), s.sizing->sizes());
  EXPECT_EQ(back.sizing->hMax(), s.sizing->hMax());
  const Points P = pointsInside(s.cage, 200, 3);
  EXPECT_LE((back.field->weightsAt(P) - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
}

/// Points d = 1, 2, 3 px from a gap's side x = `side` inside the cage (x = side − d·direction),
/// at heights y0..y1.
Points besideGap(double side, double direction, double y0, double y1) {
  std::vector<Vec2> got;
  for (int d = 1; d <= 3; ++d)
    for (double y = y0; y <= y1; y += 10.0) got.emplace_back(side - d * direction, y);
  Points P(Index(got.size()), 2);
  for (std::size_t i = 0; i < got.size(); ++i) P.row(Index(i)) = got[i];
  return P;
}

/// The largest weight of `controls` at P.
double weightOf(const Session& s, const Points& P, const std::vector<Index>& controls) {
  const Weights W = s.field->weightsAt(P);
  double most = 0.0;
  for (Index i = 0; i < P.rows(); ++i) {
    EXPECT_NEAR(W.row(i).sum(), 1.0, 1e-9) << "point " << i << " is not inside the cage";
    for (Index c : controls) most = std::max(most, W(i, c));
  }
  return most;
}

// The mesh has no triangle across a gap outside the cage, so a control's weight reaches the far
// side only along the cage interior (around the slit's end, up and down a leg): there it is what
// ADMM leaves of a zero at its tolerance: measured at most 6.5e-6 (slit) and 1.2e-7 (person).
constexpr double kAcrossGap = 1e-5;

TEST(LbcNarrowCage, ControlsAcrossTheSlitWeighNothingBesideIt) {
  // slit-narrow: the slit x in [148.5, 151.5] for y in 50..200; the left part's controls 0-2,
  // the right part's 3-5.
  const Session& slit = boundLbc("slit-narrow").session;
  EXPECT_LE(weightOf(slit, besideGap(148.5, 1.0, 60.0, 150.0), {4, 5}), kAcrossGap);
  EXPECT_LE(weightOf(slit, besideGap(151.5, -1.0, 60.0, 150.0), {0, 1}), kAcrossGap);
}

TEST(LbcNarrowCageSlow, ControlsAcrossThePersonsGapsWeighNothingBesideThem) {
  // person-narrow: the left leg's inner side x = 198 (controls 13, 14), the right leg's x = 202
  // (controls 9-12), 4 px apart for y in 322..470; the right arm's inner side x = 246 (controls
  // 5, 6), 6 px from the torso's x = 240 (controls 7, 8) for y in 136..280.
  const Session& person = boundLbc("person-narrow").session;
  EXPECT_LE(weightOf(person, besideGap(198.0, 1.0, 340.0, 460.0), {9, 10, 11}), kAcrossGap);    // left leg; the right foot
  EXPECT_LE(weightOf(person, besideGap(202.0, -1.0, 340.0, 460.0), {14, 15, 16}), kAcrossGap);  // right leg; the left foot
  EXPECT_LE(weightOf(person, besideGap(246.0, -1.0, 150.0, 270.0), {8, 9, 10, 11}), kAcrossGap);  // the arm; hip and legs
  EXPECT_LE(weightOf(person, besideGap(240.0, 1.0, 150.0, 270.0), {3, 4}), kAcrossGap);  // the torso; the hand
}

}  // namespace
}  // namespace kc::app
