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

/// A bind at h = 8 with the default parameters changed by `configure`.
std::function<Session(const Cage&, int, int)> binder(std::function<void(BindParams&)> configure) {
  return [configure](const Cage& cage, int w, int h) {
    BindParams p;
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
// measured when the suite was written, times 1.05 rounded up to two digits. Edge linearity is
// measured every h/8 along every edge since 2026-11-30 (16 points per edge before: the star's
// 0.021 was 0.040 measured densely).

const BackendCase kCases[] = {
    kc("kc_qp_exact", Method::QP, InterpMode::Exact, InitMethod::HeatLinear, {{"checker", 0.0018}, {"star", 0.043}, {"figure", 0.12}},
       {{"checker", 0.0017}, {"star", 0.011}, {"figure", 0.14}}),
    kc("kc_qec_exact", Method::QEC, InterpMode::Exact, InitMethod::HeatLinear, {{"checker", 0.0086}, {"star", 0.042}, {"figure", 0.091}},
       {{"checker", 0.0095}, {"star", 0.011}, {"figure", 0.042}}),
    kc("kc_l1_exact", Method::L1, InterpMode::Exact, InitMethod::HeatLinear, {{"checker", 0.011}, {"star", 0.042}, {"figure", 0.091}},
       {{"checker", 0.013}, {"star", 0.011}, {"figure", 0.042}}),
    kc("kc_qp_thesis", Method::QP, InterpMode::Thesis, InitMethod::HeatLinear, {{"checker", 0.0018}, {"star", 0.042}, {"figure", 0.14}},
       {{"checker", 0.0014}, {"star", 0.011}, {"figure", 0.16}}),
    kc("kc_qp_exact_impulse", Method::QP, InterpMode::Exact, InitMethod::HeatImpulse, {{"checker", 0.0018}, {"star", 0.052}, {"figure", 0.13}},
       {{"checker", 0.0021}, {"star", 0.015}, {"figure", 0.11}}),
    kc("kc_l1_exact_invdist", Method::L1, InterpMode::Exact, InitMethod::InverseDistance, {{"checker", 0.0056}, {"star", 0.11}, {"figure", 0.41}},
       {{"checker", 0.12}, {"star", 0.58}, {"figure", 3.7}}),
    kcLinearEdges({{"checker", 0.024}, {"star", 0.13}, {"figure", 1.2}}),
    // KC on LBC targets (--init lbc: LBC on a mesh of 2h inside, heat-linear outside).
    kc("kc_qp_exact_lbc_init", Method::QP, InterpMode::Exact, InitMethod::Lbc, {{"checker", 0.0018}, {"star", 0.023}, {"figure", 0.12}},
       {{"checker", 0.0017}, {"star", 0.012}, {"figure", 0.18}}),
    lbc("lbc_square", LbcTau::Square),
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

INSTANTIATE_TEST_SUITE_P(Backends, WeightConformance,
                         ::testing::Combine(::testing::ValuesIn(caseNames()), ::testing::Values("star")), paramName);
INSTANTIATE_TEST_SUITE_P(Backends, WeightConformanceSlow,
                         ::testing::Combine(::testing::ValuesIn(caseNames()), ::testing::Values("checker", "figure")), paramName);

}  // namespace
}  // namespace kc::app
