#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "kc/app/errors.h"
#include "kc/app/field_sampler.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"

namespace kc::app {
namespace {

Cage squareCage() {
  Points C(4, 2);
  C << 12, 12, 52, 12, 52, 52, 12, 52;
  return Cage::polygon(C);
}

Session smallSession() {
  BindParams p;
  p.spacing = 4.0;
  return bind(squareCage(), 64, 64, p);
}

TEST(Session, SaveLoadRoundTripIsBitExact) {
  const auto dir = test::scratchDir("session_roundtrip");
  Session s = smallSession();
  s.pose = restPose(4);
  s.pose[1].translate = Vec2(3, -2);
  s.pose[2].rotate = 0.25;
  const std::string path = (dir / "s.kcw.json").string();
  saveSession(path, s);
  const Session t = loadSession(path);
  EXPECT_EQ(t.samples.X, s.samples.X);
  EXPECT_EQ(t.samples.kind, s.samples.kind);
  EXPECT_EQ(t.samples.edge, s.samples.edge);
  EXPECT_EQ(t.W0, s.W0);
  EXPECT_EQ(t.W, s.W);
  EXPECT_EQ(t.sigma, s.sigma);
  ASSERT_EQ(t.pose.size(), 4u);
  EXPECT_EQ(t.pose[1].translate, Vec2(3, -2));
  EXPECT_EQ(t.pose[2].rotate, 0.25);
  Points P(3, 2);
  P << 20, 30, 40.5, 17.25, 1, 63;
  EXPECT_EQ(t.field.weightsAt(P), s.field.weightsAt(P));
}

TEST(Session, CorruptFieldsAreNamed) {
  const auto dir = test::scratchDir("session_corrupt");
  const Session s = smallSession();
  const nlohmann::json good = nlohmann::json::parse(sessionToJson(s));
  auto expectError = [&](const nlohmann::json& j, const std::string& part) {
    const std::string path = (dir / "bad.kcw.json").string();
    test::writeText(path, j.dump());
    try {
      loadSession(path);
      ADD_FAILURE() << "no error for " << part;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  nlohmann::json j = good;
  j["weights"]["optimized"].erase(j["weights"]["optimized"].begin());
  expectError(j, "weights.optimized has");
  j = good;
  j["weights"]["initial"][5] = {0.5};
  expectError(j, "weights.initial[5] must have 4 weights");
  j = good;
  j["samples"]["kinds"][7] = "inside";
  expectError(j, "samples.kinds[7]");
  j = good;
  j["samples"]["points"][0] = {0, 0};
  expectError(j, "differs from cage point 0");
  j = good;
  j["params"]["method"] = "newton";
  expectError(j, "params.method");
  j = good;
  j["params"]["sigma"] = -1;
  expectError(j, "params.sigma");
  j = good;
  j["version"] = 7;
  expectError(j, "unsupported version 7");
  j = good;
  j["pose"] = {{"handles", nlohmann::json::array({nlohmann::json::object()})}};
  expectError(j, "pose.handles has 1 entries but the cage has 4");
  const std::string text = sessionToJson(s);
  test::writeText(dir / "cut.kcw.json", text.substr(0, text.size() / 2));
  EXPECT_THROW(loadSession((dir / "cut.kcw.json").string()), InputError);
}

TEST(Session, ReoptimizeSubsetTouchesOnlyThoseRows) {
  Session s = smallSession();
  const Weights before = s.W;
  // Paint: change the targets of a few interior samples, re-optimize only them.
  std::vector<Index> painted;
  for (Index i = 0; i < s.samples.size() && painted.size() < 5; ++i)
    if (s.samples.kind[static_cast<std::size_t>(i)] == SampleKind::Interior) painted.push_back(i);
  ASSERT_EQ(painted.size(), 5u);
  for (Index i : painted) s.W0(i, 0) += 0.3;
  std::vector<Index> columns;
  reoptimize(s, Method::QP, painted, &columns);
  EXPECT_FALSE(columns.empty());
  // Only the changed columns were re-solved, yet the field equals a full solve.
  const KernelCoefficients full = s.field.interpolator.solve(s.W);
  EXPECT_LT((full.U - s.field.coefficients.U).cwiseAbs().maxCoeff(), 1e-9 * full.U.cwiseAbs().maxCoeff());
  EXPECT_LT((full.B - s.field.coefficients.B).cwiseAbs().maxCoeff(), 1e-9);
  for (Index c = 0; c < s.W.cols(); ++c) {
    const bool listed = std::find(columns.begin(), columns.end(), c) != columns.end();
    bool differs = false;
    for (Index i : painted) differs = differs || s.W(i, c) != before(i, c);
    EXPECT_EQ(listed, differs) << "column " << c;
  }
  Index changed = 0;
  for (Index i = 0; i < s.samples.size(); ++i) {
    const bool isPainted = std::find(painted.begin(), painted.end(), i) != painted.end();
    if (!isPainted) {
      EXPECT_EQ(s.W.row(i), before.row(i)) << "row " << i;
    } else if (s.W.row(i) != before.row(i)) {
      ++changed;
    }
  }
  EXPECT_GT(changed, 0);
}

TEST(FieldSampler, MatchesTheFieldAndUpdatesOnlyGivenColumns) {
  Session s = smallSession();
  Points P(200, 2);
  for (Index i = 0; i < P.rows(); ++i) P.row(i) << 0.3 * static_cast<double>(i % 20) * 10.0 + 1.5, 0.31 * static_cast<double>(i / 10) * 10.0;
  const FieldSampler sampler(s.field, P);
  const Weights direct = s.field.weightsAt(P);
  Weights W = sampler.evaluate(s.field.coefficients);
  EXPECT_LT((W - direct).cwiseAbs().maxCoeff(), 1e-12);
  // Change the coefficients of column 2 only: updating column 2 alone gives the full result.
  KernelCoefficients coef = s.field.coefficients;
  coef.U.col(2) *= 0.5;
  coef.B.col(2) *= 0.5;
  const Weights expected = sampler.evaluate(coef);
  const Weights old = W;
  const Index cols[] = {2};
  sampler.updateColumns(coef, cols, W);
  EXPECT_LT((W - expected).cwiseAbs().maxCoeff(), 1e-14);
  for (Index c : {0, 1, 3}) EXPECT_EQ(W.col(c), old.col(c));
  EXPECT_NE(W.col(2), old.col(2));
}

}  // namespace
}  // namespace kc::app
