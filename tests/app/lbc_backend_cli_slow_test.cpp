// The LBC backend through kcwarp-cli, end to end: bind, stats, and its answers to what LBC cannot
// do (exit 2, one line). Labelled slow: it runs the built program several times.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_run.h"

namespace kc::app {
namespace {

namespace fs = std::filesystem;

const std::string kImages = std::string(KC_SOURCE_DIR) + "/images/";

TEST(LbcBackendCli, BindStatsAndWhatItCannotDo) {
  const fs::path dir = test::scratchDir("lbc_cli");
  const std::string cage = "'" + kImages + "star.cage.json'", image = "'" + kImages + "star.png'";
  auto r = test::runCli(
      "bind --backend lbc --spacing 10 --lbc-tau linear --lbc-gap 0.001 --cage " + cage + " --image " + image + " -o s.kcw.json",
      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("LBC mesh of"), std::string::npos) << r.out;
  r = test::runCli("stats --json --session s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json st = nlohmann::json::parse(r.out);
  EXPECT_LE(st["properties"]["inside"]["partition_of_unity"].get<double>(), 1e-9);
  EXPECT_LT(st["locality"]["mean_influencing"].get<double>(), 10.0);
  // No whole-image row (LBC has no weights outside the cage); LBC's own parameters and solver report.
  EXPECT_TRUE(st["properties"]["image"].is_null());
  EXPECT_FALSE(st["properties"]["outside_weights"].get<bool>());
  EXPECT_EQ(st["backend"], "lbc");
  EXPECT_FALSE(st.contains("method") || st.contains("sigma")) << "KC's parameters mean nothing here";
  EXPECT_EQ(st["lbc"]["tau"], "linear");
  EXPECT_EQ(st["lbc"]["gap"], 0.001);
  const nlohmann::json& lbc = st["solver"]["lbc"];
  EXPECT_TRUE(lbc["converged"].get<bool>());
  EXPECT_GE(lbc["objective"].get<double>(), lbc["lower_bound"].get<double>());
  EXPECT_LE(lbc["objective"].get<double>(), 1.001 * lbc["lower_bound"].get<double>()) << "certified within 0.1%";
  EXPECT_GT(st["locality"]["compact_fraction"].get<double>(), 0.0);
  r = test::runCli("stats --session s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("whole image"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("outside the cage"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("LBC mesh of the cage interior"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("lower bound"), std::string::npos) << r.out;
  // A warp of the session without --outside pins the border and lets the background follow, as
  // for a kc session (no copy of the moved part left behind where it was).
  nlohmann::json pose = {{"version", 1}, {"positions", nlohmann::json::parse(test::slurp(kImages + "star.cage.json"))["points"]}};
  pose["positions"][0][0] = pose["positions"][0][0].get<double>() + 30.0;
  test::writeText(dir / "pose.json", pose.dump());
  r = test::runCli("warp --session s.kcw.json --pose pose.json -o pinned.png", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("outside pinned"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pinned exterior"), std::string::npos) << r.out;

  struct Bad {
    std::string args, says;
  } bad[] = {
      {"bind --backend lbc --lbc-max-iterations 2 --cage " + cage + " --image " + image + " -o x.kcw.json", "did not converge"},
      {"bind --backend lbc --spacing 0.06 --cage " + cage + " --image " + image + " -o x.kcw.json", "larger --spacing"},
      {"bind --backend lbc --lbc-tau cubic --cage " + cage + " --image " + image + " -o x.kcw.json", "--lbc-tau"},
      {"bind --backend lbc --lbc-tolerance 0 --cage " + cage + " --image " + image + " -o x.kcw.json", "--lbc-tolerance"},
      {"bind --backend lbc --lbc-gap 0 --cage " + cage + " --image " + image + " -o x.kcw.json", "--lbc-gap"},
      {"bind --backend lbc --lbc-gap nan --cage " + cage + " --image " + image + " -o x.kcw.json", "--lbc-gap"},
      {"warp --session s.kcw.json --outside deform -o w.png", "deform"},
  };
  for (const Bad& b : bad) {
    r = test::runCli(b.args, dir);
    EXPECT_EQ(r.code, 2) << b.args << "\n" << r.err;
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(b.says), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "x.kcw.json"));
  EXPECT_FALSE(fs::exists(dir / "w.png"));
}

TEST(LbcBackendCli, BindsANarrowCageAtAnAutomaticSpacingOnAGradedMesh) {
  // The slit 3 px wide: no --spacing, no refusal; the spacing from the mesh's vertex budget, the
  // mesh finer at the slit; stats sees exact barycentric weights inside.
  const fs::path dir = test::scratchDir("lbc_cli_narrow");
  const std::string cage = "'" + std::string(KC_SOURCE_DIR) + "/tests/data/narrow/slit-narrow.cage.json'";
  auto r = test::runCli("bind --backend lbc --size 300x300 --cage " + cage + " -o s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("spacing: automatic 9.46 px (an LBC mesh of about 1200 vertices"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("graded: mesh spacing 3-9.46 px"), std::string::npos) << r.out;
  r = test::runCli("stats --json --session s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json st = nlohmann::json::parse(r.out);
  EXPECT_LE(st["properties"]["inside"]["partition_of_unity"].get<double>(), 1e-9);
}

}  // namespace
}  // namespace kc::app
