// The conformance suite every weight backend must pass. A case is a backend factory (a bind with
// given parameters; KC with each method, interpolation mode and initialization today, LBC joins
// later); the suite asserts the properties a user relies on, measured on the coordinate field over
// the image (not only at the samples): partition of unity and reproduction, the Lagrange property,
// finite values, linearity along the cage edges, non-negativity where the method promises it, and
// a bound on the field's negative lobes inside the cage.

#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <tuple>

#include "kc/app/diagnostics.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"

namespace kc::app {
namespace {

/// Upper bounds pinned per bundled example (checker, star, figure) at the values measured when the
/// suite was written (rounded up), so that a regression shows; work on lines and rigidity will
/// tighten them.
using PerExample = std::map<std::string, double>;

struct BackendCase {
  std::string name;                                       ///< Readable test-name part.
  std::function<Session(const Cage&, int, int)> bind;     ///< The backend factory.
  bool exact = true;              ///< Partition of unity and reproduction to round-off everywhere.
  bool nonNegative = false;       ///< w ≥ 0 at interior samples (inside the control hull).
  bool outsideCage = true;        ///< The field has weights outside the cage (else only inside is checked).
  double sampleUnity = 1e-12;     ///< Partition of unity at the samples (round-off of the rows' sums).
  PerExample edgeLinearity;       ///< max deviation from linear weights along cage edges (4.7).
  PerExample negativeLobe;        ///< −(min weight of the field inside the cage).
};

/// A bind at h = 8 of the whole frame (the properties are measured outside the cage too) with the
/// default parameters changed by `configure`.
std::function<Session(const Cage&, int, int)> binder(std::function<void(BindParams&)> configure) {
  return [configure](const Cage& cage, int w, int h) {
    BindParams p = frameBindParams();
    p.spacing = 8.0;
    configure(p);
    return app::bind(cage, w, h, p);
  };
}

BackendCase kc(std::string name, Method method, InterpMode interp, InitMethod init, PerExample edge, PerExample lobe) {
  BackendCase c;
  c.name = std::move(name);
  c.bind = binder([=](BindParams& p) {
    p.backend = "kc";
    p.kc.method = method;
    p.kc.interp = interp;
    p.kc.init.method = init;
  });
  c.exact = interp == InterpMode::Exact;
  c.nonNegative = method == Method::QP;
  c.edgeLinearity = std::move(edge);
  c.negativeLobe = std::move(lobe);
  return c;
}

/// The default bind with `--linear-edges` (the field post-processed to be linear along every cage
/// edge, thesis 5.3.3): linearity ≤ 1e-3 everywhere along the edges is the goal it is held to.
BackendCase kcLinearEdges(PerExample lobe) {
  BackendCase c = kc("kc_qp_exact_linear_edges", Method::QP, InterpMode::Exact, InitMethod::HeatLinear,
                     {{"checker", 1e-3}, {"star", 1e-3}, {"figure", 1e-3}}, std::move(lobe));
  c.bind = binder([](BindParams& p) { p.kc.linearEdges = true; });
  c.nonNegative = false;  // the post-processing changes the weights of samples near the edges
  c.sampleUnity = 1e-11;  // it adds K·ΔU, entries of order 1, to those rows: their sums carry that round-off
  return c;
}

/// Local barycentric coordinates: exact barycentric, w ≥ 0, exactly linear on the cage edges, on
/// the cage interior only.
BackendCase lbc(std::string name, LbcTau tau) {
  BackendCase c;
  c.name = std::move(name);
  c.bind = binder([=](BindParams& p) {
    p.backend = "lbc";
    p.lbc.tau = tau;
  });
  c.nonNegative = true;
  c.outsideCage = false;
  c.edgeLinearity = {{"checker", 1e-12}, {"star", 1e-12}, {"figure", 1e-12}};
  c.negativeLobe = {{"checker", 1e-15}, {"star", 1e-15}, {"figure", 1e-15}};  // round-off of barycentric interpolation
  return c;
}

/// The test backend of tests/support/mvc_backend.cpp (mean value coordinates, registered there):
/// exact barycentric on the cage interior, linear on the edges, positive in the star (star-shaped
/// about its centre), down to −0.12 in the figure's concave parts (measured 2026-12-06, × 1.05).
BackendCase mvc() {
  BackendCase c;
  c.name = "mvc_test_backend";
  c.bind = binder([](BindParams& p) { p.backend = "mvc"; });
  c.outsideCage = false;
  c.edgeLinearity = {{"checker", 1e-12}, {"star", 1e-12}, {"figure", 1e-12}};
  c.negativeLobe = {{"checker", 1e-15}, {"star", 1e-15}, {"figure", 0.13}};
  return c;
}

const BackendCase& caseNamed(const std::string& name);

class WeightConformance : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {
 protected:
  void SetUp() override {
    const auto& [caseName, example] = GetParam();
    const std::string dir = std::string(KC_SOURCE_DIR) + "/images/";
    const Cage cage = loadCage(dir + example + ".cage.json");
    const int w = example == "figure" ? 320 : 320, h = example == "figure" ? 400 : 320;
    session = caseNamed(caseName).bind(cage, w, h);
    diagnostics = diagnose(session, 40000);
  }
  Session session;
  Diagnostics diagnostics;
};

/// Every property of the suite for one case on one example.
void expectProperties(const std::string& caseName, const std::string& example, const Session& s, const Diagnostics& d) {
  const BackendCase& c = caseNamed(caseName);
  const Index m = s.cage.size();
  ASSERT_TRUE(s.hasField());

  // Finite values, at the samples and in the field over the whole image.
  ASSERT_TRUE(s.W.allFinite());
  ASSERT_TRUE(std::isfinite(d.image.partitionOfUnity) && std::isfinite(d.image.reproduction) && std::isfinite(d.image.minWeight));

  // At the samples the optimizers enforce the constraints exactly; controls are Lagrange (3.18).
  EXPECT_LT(d.samples.partitionOfUnity, c.sampleUnity);
  EXPECT_LT(d.samples.reproduction, 1e-9);  // pixels
  for (Index i = 0; i < m; ++i)
    for (Index k = 0; k < m; ++k) EXPECT_EQ(s.W(i, k), i == k ? 1.0 : 0.0) << "Lagrange at sample " << i;
  // Edge samples use only their edge's two controls (4.7).
  for (Index i = 0; i < s.samples.size(); ++i) {
    if (s.samples.kind[static_cast<std::size_t>(i)] != SampleKind::Edge) continue;
    const int a = s.samples.edge(i, 0), b = s.samples.edge(i, 1);
    EXPECT_NEAR(s.W.row(i).sum() - s.W(i, a) - s.W(i, b), 0.0, 1e-12) << "edge sample " << i << " uses other controls";
  }

  if (c.exact) {
    // The field everywhere in the image (inside the cage for a field without weights outside), to round-off.
    const PropertyRow& where = c.outsideCage ? d.image : d.inside;
    EXPECT_GT(where.points, 1000);
    EXPECT_LE(where.partitionOfUnity, 1e-9);
    EXPECT_LE(where.reproduction, 1e-9);  // pixels
    EXPECT_LE(d.lagrange, 1e-9);
  } else {
    // The thesis's plain interpolation is approximate (~1e-3); held to that inside the cage, away
    // from the end of the sampled domain where the kernel sums fall off (thesis Fig 3.1).
    EXPECT_LT(d.inside.partitionOfUnity, 5e-3);
    EXPECT_LT(d.inside.reproduction, 0.1 * s.params.spacing);
    EXPECT_LT(d.lagrange, 1e-6);
  }

  // Linearity along the cage edges (4.7), in the field between samples (every h/8): pinned upper bounds.
  std::printf("[measured] %s %s: edge linearity %.3g, min w inside %.3g\n", caseName.c_str(), example.c_str(), d.edgeLinearity,
              d.inside.minWeight);
  EXPECT_LE(d.edgeLinearity, c.edgeLinearity.at(example)) << "edge linearity regressed";

  // Negative lobes of the field inside the cage: pinned upper bound on −min w.
  EXPECT_GE(d.inside.minWeight, -c.negativeLobe.at(example)) << "negative lobe inside the cage grew";

  if (c.nonNegative) {
    // The per-sample QP is feasible inside the control points' hull, which holds the whole cage:
    // every interior sample's weights are ≥ 0.
    for (Index i = 0; i < s.samples.size(); ++i) {
      if (s.samples.kind[static_cast<std::size_t>(i)] == SampleKind::Interior) {
        ASSERT_GE(s.W.row(i).minCoeff(), -1e-12) << "interior sample " << i;
      }
    }
  }
}

// Every case on the star (non-convex, 10 controls) in the fast run; the same cases on the checker
// and the figure (30 controls, the slowest binds) under the slow label.
class WeightConformanceSlow : public WeightConformance {};

TEST_P(WeightConformance, PropertiesHold) {
  expectProperties(std::get<0>(GetParam()), std::get<1>(GetParam()), session, diagnostics);
}

TEST_P(WeightConformanceSlow, PropertiesHold) {
  expectProperties(std::get<0>(GetParam()), std::get<1>(GetParam()), session, diagnostics);
}

// Edge linearity and negative-lobe bounds per example (checker, star, figure) at h = 8: the values
// measured with the local default (screened targets, KcParams::guardLobes; 2026-12-03), times 1.05
// rounded up to two digits; re-measured where the floored targets (kTargetFloor, 2026-12-06; 0.04
// 2026-12-07) went past a bound: QEC and L1 on the figure (edge linearity 0.113), their lobes and
// those of the thesis interpolation and linear edges (QEC star −0.0274, checker −0.0069; L1 −0.0460,
// −0.0261; thesis star −0.0121, figure edge linearity 0.0571; linear edges figure −0.536). Edge linearity is
// measured every h/8 along every edge since 2026-11-30 (16 points per edge before: the star's
// 0.021 was 0.040 measured densely).

const BackendCase kCases[] = {
    kc("kc_qp_exact", Method::QP, InterpMode::Exact, InitMethod::HeatLinear,
       {{"checker", 0.0024}, {"star", 0.021}, {"figure", 0.069}}, {{"checker", 0.0054}, {"star", 0.012}, {"figure", 0.067}}),
    kc("kc_qec_exact", Method::QEC, InterpMode::Exact, InitMethod::HeatLinear,
       {{"checker", 0.0024}, {"star", 0.021}, {"figure", 0.12}}, {{"checker", 0.0073}, {"star", 0.029}, {"figure", 0.075}}),
    kc("kc_l1_exact", Method::L1, InterpMode::Exact, InitMethod::HeatLinear,
       {{"checker", 0.0062}, {"star", 0.021}, {"figure", 0.12}}, {{"checker", 0.028}, {"star", 0.049}, {"figure", 0.075}}),
    kc("kc_qp_thesis", Method::QP, InterpMode::Thesis, InitMethod::HeatLinear,
       {{"checker", 0.0035}, {"star", 0.024}, {"figure", 0.06}}, {{"checker", 0.012}, {"star", 0.013}, {"figure", 0.05}}),
    kc("kc_qp_exact_impulse", Method::QP, InterpMode::Exact, InitMethod::HeatImpulse,
       {{"checker", 0.002}, {"star", 0.05}, {"figure", 0.13}}, {{"checker", 0.0038}, {"star", 0.013}, {"figure", 0.03}}),
    kc("kc_l1_exact_invdist", Method::L1, InterpMode::Exact, InitMethod::InverseDistance,
       {{"checker", 0.0032}, {"star", 0.099}, {"figure", 0.56}}, {{"checker", 0.12}, {"star", 0.58}, {"figure", 3.7}}),
    kcLinearEdges({{"checker", 0.0071}, {"star", 0.068}, {"figure", 0.57}}),
    // KC on LBC targets (--init lbc: LBC on a mesh of 2h inside, heat-linear outside). The figure's
    // deepest weight inside over seeds 1-5: −0.035 to −0.050 (−0.035 to −0.050 before the graded
    // start kept each side's count; seed 1 −0.042 then, −0.050 now).
    kc("kc_qp_exact_lbc_init", Method::QP, InterpMode::Exact, InitMethod::Lbc,
       {{"checker", 0.002}, {"star", 0.023}, {"figure", 0.07}}, {{"checker", 0.0038}, {"star", 0.013}, {"figure", 0.052}}),
    lbc("lbc_square", LbcTau::Square),
    mvc(),
};

const BackendCase& caseNamed(const std::string& name) {
  for (const BackendCase& c : kCases)
    if (c.name == name) return c;
  throw std::logic_error("no conformance case " + name);
}

std::vector<std::string> caseNames() {
  std::vector<std::string> names;
  for (const BackendCase& c : kCases) names.push_back(c.name);
  return names;
}

std::string paramName(const ::testing::TestParamInfo<std::tuple<std::string, std::string>>& info) {
  return std::get<0>(info.param) + "_" + std::get<1>(info.param);
}

// Locality of the default bind (what a person sees dragging one control 40 px: the area that moves
// ≥ 0.5 px, Diagnostics::drag) against the LBC backend's at its defaults but solved to a certified
// 0.1% optimality gap (the reference: the default stops at 1%), and the depth of the
// default bind's negative lobes inside the cage, on the bundled star and figure, two cages drawn
// by hand (tests/data/locality: a person, a hand with fingers 6-10 px apart) and a picture-sized
// rectangle with its edges' midpoints (8 controls, deep: the locality length follows its depth),
// each at the automatic spacing. The goals are an area ≤ 1.1× LBC's and lobes ≥ −0.02: every case
// is held to both (the default's lobe bound, KcParams::lobeBound, holds the lobes at −kLobeDepth).
struct LocalityCase {
  std::string cage;   ///< path from the source directory
  int width, height;  ///< the picture
  double areaRatio;   ///< bound on the mean drag area over LBC's
  double lobe;        ///< bound on −(deepest weight inside the cage)
};

/// lbcGap > 0: the LBC backend's optimality gap (LbcParams::gap).
Session bindDefault(const Cage& cage, int w, int h, const std::string& backend, double lbcGap = 0.0) {
  BindParams p;
  p.backend = backend;
  if (lbcGap > 0.0) p.lbc.gap = lbcGap;
  p.exterior = sampling::ExteriorExtent::Band;  // as kcwarp-cli bind and the GUI
  p.spacing = automaticSpacing(cage, w, h, p);
  return app::bind(cage, w, h, p);
}

TEST(LocalityConformanceSlow, DefaultBindIsNearlyAsLocalAsLbcWithShallowLobes) {
  const LocalityCase cases[] = {
      {"images/star.cage.json", 320, 320, 1.1, 0.02},
      {"images/figure.cage.json", 320, 400, 1.1, 0.02},
      {"tests/data/locality/person.cage.json", 360, 500, 1.1, 0.02},
      {"tests/data/locality/hand.cage.json", 400, 440, 1.1, 0.02},
      {"tests/data/locality/rectangle.cage.json", 720, 477, 1.0, 0.02},
  };
  for (const LocalityCase& c : cases) {
    SCOPED_TRACE(c.cage);
    const Cage cage = loadCage(std::string(KC_SOURCE_DIR) + "/" + c.cage);
    const Session kc = bindDefault(cage, c.width, c.height, "kc"), lbc = bindDefault(cage, c.width, c.height, "lbc", 0.001);
    const Diagnostics dk = diagnose(kc, 100000), dl = diagnose(lbc, 100000);
    ASSERT_EQ(dk.drag.step, 2);
    ASSERT_GT(dl.drag.mean, 0.0);
    const double ratio = dk.drag.mean / dl.drag.mean;
    std::printf("[measured] %s: drag area %.1f%% (LBC %.1f%%, ratio %.2f), deepest weight %.4f\n", c.cage.c_str(), 100 * dk.drag.mean,
                100 * dl.drag.mean, ratio, dk.drag.minWeight);
    EXPECT_LE(ratio, c.areaRatio);
    EXPECT_GE(dk.drag.minWeight, -c.lobe);
    EXPECT_GE(dk.inside.minWeight, -kLobeDepth - 1e-12);
    EXPECT_LE(dk.inside.partitionOfUnity, 1e-9);
    EXPECT_LE(dk.inside.reproduction, 1e-7);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, WeightConformance,
                         ::testing::Combine(::testing::ValuesIn(caseNames()), ::testing::Values("star")), paramName);
INSTANTIATE_TEST_SUITE_P(Backends, WeightConformanceSlow,
                         ::testing::Combine(::testing::ValuesIn(caseNames()), ::testing::Values("checker", "figure")), paramName);

}  // namespace
}  // namespace kc::app
