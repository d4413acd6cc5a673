// The bundled stick figure (thesis 6.2.2, Table 6.6): a cage made of a closed loop around the head
// and open sticks. The head's loop bounds an interior (sampled, weights inside); the sticks carry
// linear weights at their samples; reproduction, partition of unity and Lagrange hold with every
// optimization method, in the field over the whole image.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <ostream>
#include <nlohmann/json.hpp>
#include <string>

#include "kc/app/diagnostics.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"

namespace kc {
/// Test names and failure messages show the method's name (gtest and ctest), not its bytes.
inline void PrintTo(Method method, std::ostream* os) { *os << toString(method); }
}  // namespace kc

namespace kc::app {
namespace {

Cage stickCage() { return loadCage((std::filesystem::path(KC_SOURCE_DIR) / "images" / "stick.cage.json").string()); }

TEST(StickFigure, HeadLoopHasAnInsideAndSticksDoNot) {
  const Cage cage = stickCage();
  ASSERT_FALSE(cage.closed);
  EXPECT_EQ(loopEdges(cage).size(), 8u);  // the head's 8-point loop; the 6 sticks bound nothing
  EXPECT_EQ(cageEdges(cage).size(), 14u);
  EXPECT_TRUE(insideCage(cage, Vec2(160, 72)));    // the head's centre
  EXPECT_FALSE(insideCage(cage, Vec2(160, 220)));  // on the torso's side
  EXPECT_FALSE(insideCage(cage, Vec2(120, 200)));  // between an arm and the torso
}

/// Binds the stick figure at spacing h with `method` and checks Table 6.6's properties, the field
/// diagnosed at `points` points.
void expectTableSixSixProperties(Method method, double h, Index points) {
  const Cage cage = stickCage();
  BindParams p;
  p.spacing = h;
  p.kc.method = method;
  const Session s = bind(cage, 320, 400, p);
  // The head is sampled (it got none while an open cage had no inside).
  Index head = 0;
  for (Index i = 0; i < s.samples.size(); ++i)
    if (s.samples.kind[std::size_t(i)] == SampleKind::Interior) {
      ++head;
      EXPECT_TRUE(insideCage(cage, s.samples.X.row(i).transpose())) << "interior sample " << i << " outside the head";
    }
  EXPECT_GT(head, 50);
  // Stick samples carry the linear weights of their stick's two controls (4.7, 4.13).
  Index onSticks = 0;
  for (Index i = 0; i < s.samples.size(); ++i) {
    if (s.samples.kind[std::size_t(i)] != SampleKind::Edge) continue;
    const int a = s.samples.edge(i, 0), b = s.samples.edge(i, 1);
    const Vec2 A = cage.C.row(a), B = cage.C.row(b), x = s.samples.X.row(i);
    const double t = (x - A).dot(B - A) / (B - A).squaredNorm();
    EXPECT_NEAR(s.W(i, a), 1.0 - t, 1e-9);
    EXPECT_NEAR(s.W(i, b), t, 1e-9);
    ++onSticks;
  }
  EXPECT_GT(onSticks, 50);

  const Diagnostics d = diagnose(s, points);
  EXPECT_GT(d.inside.points, 1000);
  EXPECT_LE(d.image.partitionOfUnity, 1e-9);
  EXPECT_LE(d.image.reproduction, 1e-9);  // pixels
  EXPECT_LE(d.lagrange, 1e-9);
  ASSERT_TRUE(d.sticks);
  // Linear precision on sticks is approximate (thesis Table 6.6: "not satisfied in a strict sense");
  // measured 0.031 (QP), 0.045 (QEC), 0.033 (L1) at h = 6: bounded so a regression shows.
  EXPECT_LE(d.stickLinearity, 0.08);
  std::printf("[stick %s] interior samples %ld, unity %.2g, reproduction %.2g px, Lagrange %.2g, min w inside %.3g, image %.3g, "
              "linearity along sticks %.3g, all edges %.3g\n",
              std::string(toString(method)).c_str(), long(head), d.image.partitionOfUnity, d.image.reproduction, d.lagrange,
              d.inside.minWeight, d.image.minWeight, d.stickLinearity, d.edgeLinearity);
}

class StickFigureMethods : public ::testing::TestWithParam<Method> {};
class StickFigureMethodsSlow : public ::testing::TestWithParam<Method> {};

TEST_P(StickFigureMethods, TableSixSixPropertiesHold) { expectTableSixSixProperties(GetParam(), 10.0, 40000); }

TEST_P(StickFigureMethodsSlow, TableSixSixPropertiesHoldAtAFinerSpacing) { expectTableSixSixProperties(GetParam(), 8.0, 40000); }

TEST(LinearEdges, SessionKeepsTheOptionAndSticksAreRefused) {
  const Cage star = loadCage(std::string(KC_SOURCE_DIR) + "/images/star.cage.json");
  BindParams p;
  p.spacing = 12.0;
  p.kc.linearEdges = true;
  const Session s = bind(star, 320, 320, p);
  const std::string text = sessionToJson(s);
  const Session back = sessionFromJson(text, "s.kcw.json");
  EXPECT_TRUE(back.params.kc.linearEdges);
  EXPECT_LE(diagnose(back, 20000).edgeLinearity, 1e-3);  // the reloaded field is the post-processed one
  // A session written before the option (no params.linear_edges) was not post-processed.
  nlohmann::json j = nlohmann::json::parse(text);
  j["params"].erase("linear_edges");
  EXPECT_FALSE(sessionFromJson(j.dump(), "old.kcw.json").params.kc.linearEdges);
  // The stick figure's sticks get worse with it (docs/ARCHITECTURE.md): refused, naming the option.
  try {
    bind(stickCage(), 320, 400, p);
    ADD_FAILURE() << "a cage with sticks was bound with linear edges";
  } catch (const InputError& e) {  // bad input (CLI: exit 2, one line)
    EXPECT_NE(std::string(e.what()).find("--linear-edges needs a cage without sticks"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, StickFigureMethods, ::testing::Values(Method::QP, Method::QEC, Method::L1),
                         [](const auto& info) { return std::string(toString(info.param)); });
INSTANTIATE_TEST_SUITE_P(Methods, StickFigureMethodsSlow, ::testing::Values(Method::QP, Method::QEC, Method::L1),
                         [](const auto& info) { return std::string(toString(info.param)); });

}  // namespace
}  // namespace kc::app
