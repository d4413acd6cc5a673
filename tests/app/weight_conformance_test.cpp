// The conformance suite every weight backend must pass: bind a bundled cage and check partition
// of unity, reproduction, the Lagrange property, linear weights on edge samples and finite values,
// at the samples (W) and everywhere in the image (the interpolated field). A new backend (e.g. LBC)
// is added by extending the parameter list.

#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "kc/app/diagnostics.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"

namespace kc::app {
namespace {

struct Backend {
  std::string name;  // backend + method + interpolation, for the test name
  Method method;
  InterpMode interp;
  InitMethod init;
};

class WeightConformance : public ::testing::TestWithParam<std::tuple<Backend, std::string>> {};

TEST_P(WeightConformance, PropertiesHoldOnBundledCages) {
  const auto& [backend, example] = GetParam();
  const std::string dir = std::string(KC_SOURCE_DIR) + "/images/";
  const Cage cage = loadCage(dir + example + ".cage.json");
  BindParams p;
  p.spacing = 8.0;
  p.method = backend.method;
  p.interp = backend.interp;
  p.init.method = backend.init;
  const int size = example == "figure" ? 400 : 320;
  const Session s = bind(cage, example == "figure" ? 320 : size, size, p);
  const Index m = cage.size();

  ASSERT_TRUE(s.W.allFinite());
  const Diagnostics d = diagnose(s, 40000);
  // At the samples the optimizers enforce the constraints exactly.
  EXPECT_LT(d.samples.partitionOfUnity, 1e-12);
  EXPECT_LT(d.samples.reproduction, 1e-9);  // pixels
  for (Index i = 0; i < m; ++i)
    for (Index k = 0; k < m; ++k) EXPECT_EQ(s.W(i, k), i == k ? 1.0 : 0.0) << "Lagrange at sample " << i;
  for (Index i = 0; i < s.samples.size(); ++i) {
    if (s.samples.kind[static_cast<std::size_t>(i)] != SampleKind::Edge) continue;
    const int a = s.samples.edge(i, 0), b = s.samples.edge(i, 1);
    EXPECT_NEAR(s.W.row(i).sum() - s.W(i, a) - s.W(i, b), 0.0, 1e-12) << "edge sample " << i << " uses other controls";
  }
  if (backend.interp == InterpMode::Exact) {
    // Everywhere in the image, to round-off.
    EXPECT_LT(d.image.partitionOfUnity, 1e-9);
    EXPECT_LT(d.image.reproduction, 1e-7);
    EXPECT_LT(d.lagrange, 1e-9);
  } else {
    // The thesis's plain interpolation is approximate (~1e-3); held to that inside the cage, away
    // from the end of the sampled domain where the kernel sums fall off (thesis Fig 3.1).
    EXPECT_LT(d.inside.partitionOfUnity, 5e-3);
    EXPECT_LT(d.inside.reproduction, 0.1 * p.spacing);
    EXPECT_LT(d.lagrange, 1e-6);
  }
  if (backend.method == Method::QP) {
    EXPECT_GE(d.samples.minWeight, -1.0) << "the fallback outside the control hull keeps weights bounded";
  }
}

const Backend kBackends[] = {
    {"kc_qp_exact", Method::QP, InterpMode::Exact, InitMethod::HeatLinear},
    {"kc_qec_exact", Method::QEC, InterpMode::Exact, InitMethod::HeatLinear},
    {"kc_l1_exact", Method::L1, InterpMode::Exact, InitMethod::HeatLinear},
    {"kc_qp_thesis", Method::QP, InterpMode::Thesis, InitMethod::HeatLinear},
    {"kc_qp_exact_impulse", Method::QP, InterpMode::Exact, InitMethod::HeatImpulse},
    {"kc_l1_exact_invdist", Method::L1, InterpMode::Exact, InitMethod::InverseDistance},
};

INSTANTIATE_TEST_SUITE_P(Backends, WeightConformance,
                         ::testing::Combine(::testing::ValuesIn(kBackends), ::testing::Values("checker", "star", "figure")),
                         [](const auto& info) { return std::get<0>(info.param).name + "_" + std::get<1>(info.param); });

}  // namespace
}  // namespace kc::app
