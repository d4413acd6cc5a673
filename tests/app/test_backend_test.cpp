// A backend is one class and one registration line: tests/support/mvc_backend.cpp (mean value
// coordinates) registers itself and nothing else in kcwarp names it. Here it is found by name,
// binds through app::bind and from a kcwarp-cli with it linked in (kcwarp-cli-mvc), takes its
// described parameter from the command line and the session file, and its sessions load again.
// The conformance suite (weight_conformance_test.cpp) runs on it too.

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "kc/app/backend.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"

namespace kc::test {
namespace {

const std::string kImages = std::string(KC_SOURCE_DIR) + "/images/";

TEST(TestBackend, RegisteredWithOneLineItIsAvailableByName) {
  const auto names = app::backendNames();
  ASSERT_NE(std::find(names.begin(), names.end(), "mvc"), names.end());
  EXPECT_EQ(names.front(), "kc");  // the built-in ones first
  const app::Backend& mvc = app::backendFor("mvc");
  EXPECT_EQ(mvc.displayName(), "MVC");
  ASSERT_EQ(mvc.parameters().size(), 1u);
  EXPECT_THROW(app::registerBackend(mvc), std::invalid_argument);  // a name is taken once
}

/// Only the built-in kc backend keeps its keys at the top of the session's params: a registered
/// backend with parameters and no block of its own is refused (its keys could meet another's).
TEST(TestBackend, ABackendWithParametersNeedsABlock) {
  struct Blockless final : app::Backend {
    std::string_view name() const override { return "blockless"; }
    app::BackendCapabilities capabilities() const override { return {}; }
    std::string_view displayName() const override { return "Blockless"; }
    std::string_view description() const override { return "a test"; }
    const std::vector<app::BackendParameter>& parameters() const override {
      static const std::vector<app::BackendParameter> one(1);
      return one;
    }
    void bind(app::Session&, const app::BindStep&) const override {}
    void rebuildField(app::Session&) const override {}
    OptimizeReport reoptimize(app::Session&, Method, std::span<const Index>, std::vector<Index>*) const override { return {}; }
  };
  static const Blockless blockless;
  EXPECT_THROW(app::registerBackend(blockless), std::invalid_argument);
  const auto names = app::backendNames();
  EXPECT_EQ(std::find(names.begin(), names.end(), "blockless"), names.end());
}

TEST(TestBackend, BindsThroughThePipelineWithItsParameter) {
  const Cage cage = app::loadCage(kImages + "star.cage.json");
  app::BindParams p;
  p.backend = "mvc";
  const app::Backend& mvc = app::backendFor("mvc");
  const app::BackendParameter& snap = mvc.parameters().front();  // kept by the backend
  EXPECT_EQ(app::parameterValue(mvc, snap, p), 1e-9);  // its default, not stored
  app::setParameter(mvc, snap, p, 1e-6);
  EXPECT_EQ(p.values.at("mvc.snap"), 1e-6);
  EXPECT_THROW(app::setParameter(mvc, snap, p, 2.0), std::invalid_argument);
  EXPECT_EQ(p.values.at("mvc.snap"), 1e-6);  // a refused value sets nothing
  const app::Session s = app::bind(cage, 320, 320, p);
  ASSERT_TRUE(s.hasField());
  Points P(3, 2);
  P << 160, 160, cage.C(2, 0), cage.C(2, 1), 0.5 * (cage.C(0, 0) + cage.C(1, 0)), 0.5 * (cage.C(0, 1) + cage.C(1, 1));
  const Weights W = s.field->weightsAt(P);
  EXPECT_NEAR(W.row(0).sum(), 1.0, 1e-12);
  EXPECT_NEAR((W.row(0) * cage.C - P.row(0)).norm(), 0.0, 1e-9);  // reproduction
  EXPECT_EQ(W(1, 2), 1.0);                                        // Lagrange at a control
  EXPECT_NEAR(W(2, 0), 0.5, 1e-12);                               // linear along an edge
  EXPECT_NEAR(W(2, 1), 0.5, 1e-12);
  const app::Session back = app::sessionFromJson(app::sessionToJson(s), "mem.kcw.json");
  EXPECT_EQ(back.params.values.at("mvc.snap"), 1e-6);
  EXPECT_EQ((back.field->weightsAt(P) - W).cwiseAbs().maxCoeff(), 0.0);
}

/// A field kind without a codec is not written (the load rebuilds the field); registering a codec
/// for it (registerFieldCodec) puts its block in the session and reads it back through the codec.
TEST(TestBackend, AFieldCodecKeepsItsKindsBlock) {
  const Cage cage = app::loadCage(kImages + "star.cage.json");
  app::BindParams p;
  p.backend = "mvc";
  const app::Session s = app::bind(cage, 320, 320, p);
  ASSERT_EQ(s.field->kind(), "mvc");
  EXPECT_FALSE(nlohmann::json::parse(app::sessionToJson(s)).contains("field")) << "no codec: no block";
  static int reads = 0;
  static const bool registered =
      app::registerFieldCodec({"mvc",
                               [](const app::Session& session, app::WeightsForm) {
                                 return nlohmann::json{{"kind", "mvc"}, {"controls", session.cage.size()}};
                               },
                               [](const nlohmann::json& block, app::Session& session, const std::string&) {
                                 ++reads;
                                 EXPECT_EQ(block.at("controls").get<Index>(), session.cage.size());
                                 return false;  // the backend's rebuildField makes the field
                               }});
  EXPECT_TRUE(registered);
  const auto j = nlohmann::json::parse(app::sessionToJson(s));
  ASSERT_TRUE(j.contains("field"));
  EXPECT_EQ(j["field"]["kind"], "mvc");
  const app::Session back = app::sessionFromJson(j.dump(), "mem.kcw.json");
  EXPECT_EQ(reads, 1);
  ASSERT_TRUE(back.hasField());
  Points P(1, 2);
  P << 160, 160;
  EXPECT_EQ((back.field->weightsAt(P) - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_THROW(app::registerFieldCodec({"kernel", {}, {}}), std::invalid_argument);  // a kind has one codec
  auto unknown = j;
  unknown["field"]["kind"] = "spline";
  try {
    app::sessionFromJson(unknown.dump(), "mem.kcw.json");
    ADD_FAILURE() << "an unknown field kind was read";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("\"mvc\""), std::string::npos) << e.what();  // the registered kinds are named
  }
}

TEST(TestBackend, BindsFromTheCommandLineAndItsSessionIsRead) {
  const auto dir = scratchDir("test_backend_cli");
  CliResult r = runCli("bind --help", dir, KC_MVC_CLI_PATH);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("mvc (mean value coordinates"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--mvc-snap FLOAT=1e-09"), std::string::npos) << r.out;
  r = runCli(
      "bind --backend mvc --mvc-snap 1e-7 --cage '" + kImages + "star.cage.json' --image '" + kImages + "star.png' -o s.kcw.json",
      dir, KC_MVC_CLI_PATH);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto params = nlohmann::json::parse(slurp(dir / "s.kcw.json"))["params"];
  EXPECT_EQ(params["backend"], "mvc");
  EXPECT_EQ(params["mvc"]["snap"].get<double>(), 1e-7);
  EXPECT_NE(r.out.find("bound 10 control points with MVC"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("solver: mean value coordinates of 10 control points, snap 1e-07 px; no failures"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("sigma"), std::string::npos) << "the kernel's parameters are not this backend's: " << r.out;
  // Its own report, saved in the session's reports.<block> and shown by stats, which never name it.
  const auto reports = nlohmann::json::parse(slurp(dir / "s.kcw.json"))["reports"];
  EXPECT_EQ(reports["mvc"], (nlohmann::json{{"controls", 10}, {"snap", 1e-7}}));
  r = runCli("stats --session s.kcw.json", dir, KC_MVC_CLI_PATH);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("solver: mean value coordinates of 10 control points"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  MVC: closed-form weights, nothing iterated"), std::string::npos) << r.out;
  const std::size_t at = r.out.find("  backend mvc, spacing ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string header = r.out.substr(at, r.out.find('\n', at) - at);
  EXPECT_TRUE(header.ends_with(" px, snap 1e-07")) << "its own parameter, not the kernel's σ and method: " << header;
  r = runCli("stats --session s.kcw.json --json", dir, KC_MVC_CLI_PATH);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto stats = nlohmann::json::parse(r.out);
  EXPECT_EQ(stats["solver"]["mvc"]["controls"], 10);
  EXPECT_EQ(stats["mvc"]["snap"].get<double>(), 1e-7);  // its parameters, as the session's params.mvc
  EXPECT_FALSE(stats.contains("sigma") || stats.contains("method")) << "the kernel's parameters are not this backend's";
  EXPECT_LE(stats["properties"]["inside"]["partition_of_unity"].get<double>(), 1e-9);
  EXPECT_LE(stats["properties"]["inside"]["reproduction"].get<double>(), 1e-7);
  r = runCli("bind --backend mvc --mvc-snap 5 --cage '" + kImages + "star.cage.json' --size 320,320 -o t.kcw.json", dir,
             KC_MVC_CLI_PATH);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--mvc-snap: must be a number in [1e-12, 1]"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.kcw.json"));
  // The shipped kcwarp-cli does not know it: the session names the backend it needs.
  r = runCli("stats --session s.kcw.json", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("backend 'mvc' is not available"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace kc::test
