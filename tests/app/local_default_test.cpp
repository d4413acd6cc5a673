// The default kc bind is local (screened targets, KcParams::locality) and guards its
// negative lobes (continued exterior rows, KcParams::guardLobes): painting re-derives exactly what
// a whole re-optimization would, method switches come back to the bind's weights, and sessions
// keep the options (older sessions read them off).

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "kc/app/diagnostics.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"

namespace kc::app {
namespace {

using nlohmann::json;

Cage figureCage() { return loadCage(std::string(KC_SOURCE_DIR) + "/images/figure.cage.json"); }

Session bindFigure(const BindParams& p) { return app::bind(figureCage(), 320, 400, p); }

BindParams defaults() {
  BindParams p;
  p.spacing = 10.0;
  p.exterior = sampling::ExteriorExtent::Band;
  return p;
}

TEST(LocalDefault, IsScreenedAndGuardedAndLocalerThanBefore) {
  const BindParams p = defaults();
  EXPECT_EQ(p.kc.locality, (Locality{Locality::Rule::Spacings, kLocalitySpacings}));
  EXPECT_TRUE(p.kc.guardLobes);
  // The screening and the guard, compared without the lobe bound (which holds the lobes at
  // −kLobeDepth whatever made them).
  BindParams unbounded = p;
  unbounded.kc.lobeBound = 0.0;
  BindParams before = unbounded;
  before.kc.locality = {Locality::Rule::Off, 0.0};
  before.kc.guardLobes = false;
  const Diagnostics now = diagnose(bindFigure(unbounded), 40000), old = diagnose(bindFigure(before), 40000);
  std::printf("[measured] figure h = 10: drag area %.3f (before %.3f), deepest weight %.4f (before %.4f)\n", now.drag.mean,
              old.drag.mean, now.drag.minWeight, old.drag.minWeight);
  EXPECT_LT(now.drag.mean, 0.75 * old.drag.mean);
  EXPECT_GT(now.drag.minWeight, 0.5 * old.drag.minWeight);  // lobes at most half as deep
  EXPECT_LE(now.inside.partitionOfUnity, 1e-9);
  EXPECT_LE(now.inside.reproduction, 1e-7);
}

/// The QP's allowance metric (KcParams::qpAllowance) puts the correction that restores reproduction
/// on the controls near each sample: the drag area falls, partition of unity and reproduction hold.
TEST(LocalDefault, TheCorrectionFallsOnTheNearControls) {
  const BindParams p = defaults();
  EXPECT_EQ(p.kc.qpAllowance, kQpAllowance);
  BindParams euclidean = p;
  euclidean.kc.qpAllowance = 0.0;
  const Diagnostics now = diagnose(bindFigure(p), 40000), plain = diagnose(bindFigure(euclidean), 40000);
  std::printf("[measured] figure h = 10: drag area %.4f (Euclidean QP %.4f)\n", now.drag.mean, plain.drag.mean);
  EXPECT_LT(now.drag.mean, 0.97 * plain.drag.mean);
  EXPECT_LE(now.inside.partitionOfUnity, 1e-9);
  EXPECT_LE(now.inside.reproduction, 1e-7);
  EXPECT_GE(now.inside.minWeight, plain.inside.minWeight - 0.005);  // no deeper lobes
}

TEST(LocalDefault, TheLocalityLengthFollowsTheCagesDepthInADeepCage) {
  // A 400×200 rectangle is 100 px deep: ℓ = max(1.5 h, 100/4) (within the grid's step).
  Points C(4, 2);
  C << 0, 0, 400, 0, 400, 200, 0, 200;
  const Cage rect = Cage::polygon(C);
  EXPECT_NEAR(localityLength(rect, 6.0, 1.5), 25.0, 0.5);
  EXPECT_DOUBLE_EQ(localityLength(rect, 20.0, 1.5), 30.0);  // 1.5 h beyond the depth's quarter
  Points S(4, 2);
  S << 0, 0, 400, 0, 400, 20, 0, 20;
  EXPECT_DOUBLE_EQ(localityLength(Cage::polygon(S), 6.0, 1.5), 9.0);  // a strip 10 px deep: 1.5 h
  Cage open = rect;
  open.closed = false;
  EXPECT_DOUBLE_EQ(localityLength(open, 6.0, 1.5), 9.0);  // no inside
}

TEST(LocalDefault, TheBundledFigureBindsWithEverySampleSolved) {
  // At its automatic spacing one exterior sample's QP positive set cycled among rounding-level
  // weights with the residual at 1.6e-13 (tolerance 1e-13): "1 samples not solved to optimality".
  const Image picture = loadImage(std::string(KC_SOURCE_DIR) + "/images/figure.png");
  BindParams p = defaults();
  p.spacing = automaticSpacing(figureCage(), picture.width, picture.height, p);
  const Session s = app::bind(figureCage(), Structure{}, picture.width, picture.height, p);
  EXPECT_EQ(s.report.optimize.failed, 0);
  EXPECT_FALSE(s.report.anyProblem()) << s.report.summary();
}

TEST(LocalDefault, PaintingReDerivesWhatAWholeReoptimizationGives) {
  Session painted = bindFigure(defaults()), whole = bindFigure(defaults());
  // Paint the hand control's targets up at the interior samples within 25 px of the elbow
  // (292, 178): next to the cage, where continued exterior rows read them.
  const Index hand = 6;
  std::vector<Index> stroke;
  for (Index i = 0; i < painted.samples.size(); ++i)
    if (painted.samples.kind[std::size_t(i)] == SampleKind::Interior && (painted.samples.X.row(i) - Vec2(292, 178).transpose()).norm() < 25)
      stroke.push_back(i);
  ASSERT_GT(stroke.size(), 5u);
  for (Session* s : {&painted, &whole})
    for (Index i : stroke) {
      s->W0(i, hand) += 0.3;
      s->W0.row(i) /= s->W0.row(i).sum();
    }
  std::vector<Index> columns;
  reoptimize(painted, Method::QP, stroke, &columns);
  reoptimize(whole, Method::QP);
  EXPECT_EQ((painted.W - whole.W).cwiseAbs().maxCoeff(), 0.0) << "a stroke left rows a whole re-optimization changes";
  EXPECT_TRUE(std::find(columns.begin(), columns.end(), hand) != columns.end());
  const Diagnostics d = diagnose(painted, 20000), w = diagnose(whole, 20000);
  EXPECT_LE(d.image.partitionOfUnity, 1e-9);
  EXPECT_LE(d.image.reproduction, 1e-7);
  EXPECT_NEAR(d.drag.mean, w.drag.mean, 1e-12);  // the field follows: only the changed columns were updated
  EXPECT_NEAR(d.drag.minWeight, w.drag.minWeight, 1e-9);
}

TEST(LocalDefault, MethodSwitchesComeBackToTheBindsWeights) {
  Session s = bindFigure(defaults());
  const Weights bound = s.W;
  reoptimize(s, Method::QEC);
  EXPECT_GT((s.W - bound).cwiseAbs().maxCoeff(), 1e-3);
  reoptimize(s, Method::QP);
  EXPECT_EQ((s.W - bound).cwiseAbs().maxCoeff(), 0.0);
}

/// Each rule of the targets' locality survives a session file and resolves to its length: the
/// session keys `locality` (pixels, −1 automatic) and `locality_spacings` say which.
TEST(LocalDefault, EveryLocalityRuleRoundTripsAndResolves) {
  const Cage cage = figureCage();
  Session s = bindFigure(defaults());  // a bound session; only its params change below
  using Rule = Locality::Rule;
  for (const Locality l :
       {Locality{Rule::Off, 0.0}, Locality{Rule::Spacings, 3.0}, Locality{Rule::Pixels, 20.0}, Locality{Rule::Automatic, 0.0}}) {
    BindParams p = defaults();
    p.kc.locality = l;
    s.params = p;
    const json j = json::parse(sessionToJson(s))["params"];
    EXPECT_EQ(j["locality_spacings"].get<double>(), l.rule == Rule::Spacings ? 3.0 : 0.0);
    EXPECT_EQ(j["locality"].get<double>(), l.rule == Rule::Pixels ? 20.0 : l.rule == Rule::Automatic ? -1.0 : 0.0);
    EXPECT_EQ(sessionFromJson(sessionToJson(s), "mem.kcw.json").params.kc.locality, l);
    const std::optional<double> length = locality(cage, p), sampled = locality(cage, p, true);
    switch (l.rule) {
      case Rule::Off:
        EXPECT_FALSE(length || sampled);
        break;
      case Rule::Spacings:
        EXPECT_EQ(length, localityLength(cage, p.spacing, 3.0));
        EXPECT_FALSE(sampled);  // lines made linear through the samples keep unscreened targets
        break;
      case Rule::Pixels:
        EXPECT_TRUE(length == 20.0 && sampled == 20.0);
        break;
      case Rule::Automatic:
        EXPECT_TRUE(length == automaticLocality(cage.C) && sampled == length);
        break;
    }
  }
  BindParams bad = defaults();
  for (const Locality l : {Locality{Rule::Spacings, 0.0}, Locality{Rule::Pixels, -2.0},
                           Locality{Rule::Pixels, std::numeric_limits<double>::quiet_NaN()}}) {
    bad.kc.locality = l;
    EXPECT_THROW(locality(cage, bad), std::invalid_argument);
    EXPECT_THROW(bindFigure(bad), InputError);  // the bind names itself
  }
}

TEST(LocalDefault, SessionsKeepTheOptionsAndOlderOnesReadThemOff) {
  const Session s = bindFigure(defaults());
  const Session back = sessionFromJson(sessionToJson(s), "mem.kcw.json");
  EXPECT_EQ(back.params.kc.locality, Locality{});
  EXPECT_TRUE(back.params.kc.guardLobes);
  EXPECT_EQ((back.W - s.W).cwiseAbs().maxCoeff(), 0.0);
  const Session old = loadSession(std::string(KC_SOURCE_DIR) + "/tests/data/old_format.kcw.json");
  EXPECT_EQ(old.params.kc.locality.rule, Locality::Rule::Off);
  EXPECT_FALSE(old.params.kc.guardLobes);
}

}  // namespace
}  // namespace kc::app
