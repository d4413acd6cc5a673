// End-to-end checks of kcwarp-cli bind / eval / stats: exit codes, messages and outputs.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_run.h"
#include "exif_jpeg.h"
#include "kc/app/image_io.h"

namespace kc::test {
namespace {

TEST(CliBind, BindEvalStatsOnSquare) {
  const auto dir = scratchDir("cli_bind");
  writeText(dir / "cage.json", kSquare);
  CliResult r = runCli("bind --cage cage.json --size 96,96 --spacing 4 --exterior frame -o s.kcw.json", dir);  // stats over the whole image
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "wrote s.kcw.json"));

  writeText(dir / "p.csv", "x,y\n48,48\n16,16\n30.5,70\n\n90,5\n");
  r = runCli("eval --session s.kcw.json --points p.csv -o w.csv", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(slurp(dir / "w.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "w0,w1,w2,w3");
  int rows = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    double sum = 0;
    std::string cell;
    std::vector<double> w;
    while (std::getline(ls, cell, ',')) w.push_back(std::stod(cell));
    ASSERT_EQ(w.size(), 4u);
    for (double x : w) sum += x;
    EXPECT_NEAR(sum, 1.0, 1e-9) << "row " << rows;
    if (rows == 1) {  // at control point 0: Lagrange
      EXPECT_NEAR(w[0], 1.0, 1e-6);
      EXPECT_NEAR(w[2], 0.0, 1e-6);
    }
    ++rows;
  }
  EXPECT_EQ(rows, 4);

  r = runCli("stats --session s.kcw.json --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["controls"], 4);
  EXPECT_LT(j["properties"]["image"]["partition_of_unity"].get<double>(), 1e-9);
  EXPECT_LT(j["properties"]["image"]["reproduction"].get<double>(), 1e-7);
  EXPECT_LT(j["properties"]["lagrange"].get<double>(), 1e-6);
  EXPECT_GE(j["properties"]["inside"]["min_weight"].get<double>(), -0.05);
  // The area a 40 px drag of one control moves by 0.5 px or more: on a square, each corner's
  // weight reaches 0.0125 over most of the square but not all of it.
  const auto& drag = j["locality"]["drag"];
  EXPECT_EQ(drag["weight_threshold"].get<double>(), 0.0125);
  EXPECT_EQ(drag["area_fraction"].size(), 4u);
  EXPECT_GT(drag["mean_area_fraction"].get<double>(), 0.5);
  EXPECT_LT(drag["max_area_fraction"].get<double>(), 1.0);
  EXPECT_GE(drag["max_area_fraction"].get<double>(), drag["mean_area_fraction"].get<double>());
  EXPECT_GE(drag["min_weight"].get<double>(), j["properties"]["inside"]["min_weight"].get<double>());  // a subset of its grid
  r = runCli("stats --session s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "partition of unity"));
  EXPECT_TRUE(contains(r.out, "area that moves >= 0.5 px under a 40 px drag"));
  EXPECT_TRUE(contains(r.out, "Lagrange"));
}

/// `--locality` (pixels; < 0 automatic; 0 off) replaces `--locality-spacings` (0 off); the session
/// says which rule the bind used.
TEST(CliBind, TheLocalityFlagsChooseOneRule) {
  const auto dir = scratchDir("cli_locality");
  writeText(dir / "cage.json", kSquare);
  struct Case {
    const char* flags;
    double spacings, pixels;
  };
  for (const Case& c : {Case{"", 1.5, 0.0}, Case{"--locality 0", 0.0, 0.0}, Case{"--locality 12", 0.0, 12.0},
                        Case{"--locality -3", 0.0, -1.0}, Case{"--locality-spacings 3", 3.0, 0.0},
                        Case{"--locality-spacings 0", 0.0, 0.0}, Case{"--locality 12 --locality-spacings 3", 0.0, 12.0}}) {
    const CliResult r = runCli(std::string("bind --cage cage.json --size 96,96 --spacing 8 -o s.kcw.json ") + c.flags, dir);
    ASSERT_EQ(r.code, 0) << c.flags << ": " << r.err;
    const auto params = nlohmann::json::parse(slurp(dir / "s.kcw.json"))["params"];
    EXPECT_EQ(params["locality_spacings"].get<double>(), c.spacings) << c.flags;
    EXPECT_EQ(params["locality"].get<double>(), c.pixels) << c.flags;
  }
}

/// A Boolean parameter's flag turns its default over: --linear-edges on, --no-guard-lobes and
/// --no-exact-lines off (app::parameterFlag); the session keeps what was given.
TEST(CliBind, BooleanFlagsTurnTheirDefaultOver) {
  const auto dir = scratchDir("cli_boolean_flags");
  writeText(dir / "cage.json", kSquare);
  struct Case {
    const char* flag;
    const char* key;
    bool value;
  };
  for (const Case& c : {Case{"--linear-edges", "linear_edges", true}, Case{"--no-guard-lobes", "guard_lobes", false},
                        Case{"--no-exact-lines", "exact_lines", false}}) {
    CliResult r = runCli("bind --cage cage.json --size 96,96 --spacing 8 -o s.kcw.json", dir);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(dir / "s.kcw.json"))["params"][c.key].get<bool>(), !c.value) << "default of " << c.flag;
    r = runCli(std::string("bind --cage cage.json --size 96,96 --spacing 8 -o s.kcw.json ") + c.flag, dir);
    ASSERT_EQ(r.code, 0) << c.flag << ": " << r.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(dir / "s.kcw.json"))["params"][c.key].get<bool>(), c.value) << c.flag;
  }
}

TEST(CliBind, StatsMeasureHowStraightTheStructureLinesStay) {
  const auto dir = scratchDir("cli_stats_lines");
  writeText(dir / "cage.json", R"({"version": 1, "points": [[8,8],[152,8],[152,152],[8,152]], "closed": true})");
  writeText(dir / "lines.json", R"({"version": 1, "lines": [{"points": [[40,50],[120,60]], "parallel": "p"},
                                                          {"points": [[40,100],[120,110]], "parallel": "p"}]})");
  CliResult r = runCli("bind --cage cage.json --size 160,160 --spacing 5 --structure lines.json -o s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  r = runCli("stats --session s.kcw.json --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("lines")) << r.out;
  EXPECT_EQ(j["lines"]["count"], 2);
  EXPECT_LE(j["lines"]["bend_px"].get<double>(), 0.1);
  EXPECT_GT(j["lines"]["bend_px"].get<double>(), 0.0);  // measured, not a placeholder: a kernel field is never exactly linear
  EXPECT_LE(j["lines"]["parallel_angle_deg"].get<double>(), 0.05);
  r = runCli("stats --session s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "structure lines  bend px")) << r.out;
  EXPECT_TRUE(contains(r.out, "parallel groups  angle deg")) << r.out;

  // A session without lines has no such row.
  r = runCli("bind --cage cage.json --size 160,160 --spacing 5 -o plain.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  r = runCli("stats --session plain.kcw.json --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(r.out).contains("lines"));
}

TEST(CliSample, WritesSamplesMetricsAndPicture) {
  const auto dir = scratchDir("cli_sample");
  writeText(dir / "cage.json", kSquare);
  CliResult r = runCli("sample --cage cage.json --size 96,96 --spacing 4 --seed 3 -o s.json --png s.png", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(dir / "s.json"));
  const auto& kinds = j["samples"]["kinds"];
  ASSERT_EQ(kinds.size(), j["samples"]["points"].size());
  EXPECT_EQ(kinds[0], "control");
  EXPECT_EQ(kinds[4], "edge");
  int interior = 0;
  for (const auto& k : kinds) interior += k == "interior";
  EXPECT_GT(interior, 100);  // (80-16)² / 4² = 256 cells inside, minus the band near the edges
  EXPECT_GE(j["metrics"]["separation"].get<double>(), 0.6);
  EXPECT_LE(j["metrics"]["fill"].get<double>(), 0.9);
  EXPECT_GT(std::filesystem::file_size(dir / "s.png"), 1000u);
  // Same seed, same samples.
  ASSERT_EQ(runCli("sample --cage cage.json --size 96,96 --spacing 4 --seed 3 -o t.json", dir).code, 0);
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "t.json"))["samples"], j["samples"]);
  // --png-compression: 0 stores the pixels (larger), 9 compresses at least as well as the default;
  // a level outside 0..9 is refused and writes nothing.
  ASSERT_EQ(runCli("sample --cage cage.json --size 96,96 --spacing 4 --seed 3 -o t.json --png s0.png --png-compression 0", dir).code, 0);
  ASSERT_EQ(runCli("sample --cage cage.json --size 96,96 --spacing 4 --seed 3 -o t.json --png s9.png --png-compression 9", dir).code, 0);
  EXPECT_GT(std::filesystem::file_size(dir / "s0.png"), std::filesystem::file_size(dir / "s.png"));
  EXPECT_LE(std::filesystem::file_size(dir / "s9.png"), std::filesystem::file_size(dir / "s.png"));
  r = runCli("sample --cage cage.json --size 96,96 -o v.json --png v.png --png-compression 10", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--png-compression")) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "v.png"));
  EXPECT_FALSE(std::filesystem::exists(dir / "v.json"));
  r = runCli("sample --cage cage.json --size 96,96 --spacing -1 -o u.json", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "u.json"));
}

struct BadCase {
  const char* name;
  const char* args;
  const char* message;
};

TEST(CliBind, BadInputExitsTwoWithOneLine) {
  const auto dir = scratchDir("cli_bad");
  writeText(dir / "cage.json", kSquare);
  writeText(dir / "bowtie.json", R"({"version": 1, "points": [[0,0],[50,50],[50,0],[0,50]]})");
  writeText(dir / "trunc.json", R"({"version": 1, "points": [[0,0],[50,)");
  writeText(dir / "notimage.png", "this is not a png");
  writeText(dir / "p.csv", "1,2\n3,4\n5;6\n");
  const BadCase cases[] = {
      {"missing cage", "bind --cage nope.json --size 96,96 -o s.kcw.json", "nope.json: no such file"},
      {"self-intersecting", "bind --cage bowtie.json --size 96,96 -o s.kcw.json", "bowtie.json: cage is self-intersecting"},
      {"truncated", "bind --cage trunc.json --size 96,96 -o s.kcw.json", "trunc.json: malformed JSON"},
      {"bad size", "bind --cage cage.json --size 96 -o s.kcw.json", "--size"},
      {"zero spacing", "bind --cage cage.json --size 96,96 --spacing 0 -o s.kcw.json", "spacing"},
      {"tiny spacing", "bind --cage cage.json --size 4000,4000 --spacing 0.5 --exterior frame -o s.kcw.json", "samples"},
      {"absurd size", "bind --cage cage.json --size 100000,100 -o s.kcw.json", "image size"},
      {"unknown method", "bind --cage cage.json --size 96,96 --method newton -o s.kcw.json", "--method: unknown value 'newton'"},
      {"corrupt image", "bind --cage cage.json --image notimage.png -o s.kcw.json", "notimage.png"},
      {"missing session", "eval --session none.kcw.json --points p.csv -o w.csv", "none.kcw.json: no such file"},
      {"no subcommand", "", "subcommand"},
  };
  for (const BadCase& c : cases) {
    const CliResult r = runCli(c.args, dir);
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_TRUE(contains(r.err, c.message)) << c.name << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << c.name << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "s.kcw.json"));
  // Alone, kcwarp-cli lists its subcommands; a mistyped name or option gets the likely one.
  const CliResult alone = runCli("", dir);
  EXPECT_TRUE(contains(alone.err, "bind, eval")) << alone.err;
  EXPECT_TRUE(contains(alone.out, "warp")) << "the help, with the list: " << alone.out;
  const CliResult typo = runCli("bnd --cage cage.json", dir);
  EXPECT_EQ(typo.code, 2);
  EXPECT_TRUE(contains(typo.err, "did you mean 'bind'?")) << typo.err;
  EXPECT_EQ(lineCount(typo.err), 1) << typo.err;
  const CliResult option = runCli("bind --cage cage.json --size 96,96 --spcing 6 -o s.kcw.json", dir);
  EXPECT_EQ(option.code, 2);
  EXPECT_TRUE(contains(option.err, "did you mean '--spacing'?")) << option.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "s.kcw.json"));
  // The limits are in the main help only, not repeated by every subcommand's.
  EXPECT_TRUE(contains(runCli("--help", dir).out, "Limits"));
  EXPECT_FALSE(contains(runCli("warp --help", dir).out, "Limits"));
  // bind's defaults are BindParams' own, the exterior band among them.
  EXPECT_TRUE(contains(runCli("bind --help", dir).out, "--exterior TEXT=band"));

  // A bad points row names the file and line.
  ASSERT_EQ(runCli("bind --cage cage.json --size 96,96 --spacing 6 -o s.kcw.json", dir).code, 0);
  const CliResult r = runCli("eval --session s.kcw.json --points p.csv -o w.csv", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "p.csv: line 3")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "w.csv"));
}

TEST(CliWarp, APhotoTurnedByItsExifBindsUprightAndAnOlderSessionKeepsItAsStored) {
  // A phone photo stored 48x32 and shown 32x48 (Exif orientation 6: turned 90 degrees clockwise).
  const auto dir = scratchDir("cli_exif");
  const std::string jpeg = app::encodeImage(quadrantPicture(48, 32), ".jpg");
  writeBytes(dir / "photo.jpg", withSegment(jpeg, exifSegment(orientationEntry(6, false), false)));
  writeText(dir / "cage.json", R"({"version": 1, "points": [[4,4],[28,4],[28,28],[4,28]], "closed": true})");
  CliResult r = runCli("bind --cage cage.json --image photo.jpg -o s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(slurp(dir / "s.kcw.json"));
  EXPECT_EQ(j["image_size"], nlohmann::json::parse("[32, 48]"));
  EXPECT_EQ(j["image_upright"], true);
  r = runCli("warp --session s.kcw.json -o upright.png", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Image upright = app::loadImage((dir / "upright.png").string());
  EXPECT_EQ(upright.width, 32);
  EXPECT_EQ(quadrantLayout(upright), "BRWG");  // as a viewer shows the photo (the rest pose warps nothing)

  // A session written before kcwarp read the orientation: bound on the picture as stored, and no
  // image_upright key. It warps the picture as it was bound.
  ASSERT_EQ(runCli("bind --cage cage.json --size 48,32 -o old.kcw.json", dir).code, 0);
  j = nlohmann::json::parse(slurp(dir / "old.kcw.json"));
  j["image"] = "photo.jpg";
  j.erase("image_upright");
  writeText(dir / "old.kcw.json", j.dump());
  r = runCli("warp --session old.kcw.json -o stored.png", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Image stored = app::loadImage((dir / "stored.png").string());
  EXPECT_EQ(stored.width, 48);
  EXPECT_EQ(quadrantLayout(stored), "RGBW");
  // The same session claiming an upright picture does not match it: refused, naming the picture.
  j["image_upright"] = true;
  writeText(dir / "old.kcw.json", j.dump());
  r = runCli("warp --session old.kcw.json -o refused.png", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "photo.jpg")) << r.err;
  EXPECT_TRUE(contains(r.err, "image is 32x48 but the session was bound for 48x32")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "refused.png"));
}

TEST(CliWarp, AScanTurnedByItsTiffOrientationBindsAndWarpsUpright) {
  // A TIFF stored 48x32 with Orientation 6: bound on the picture as shown (32x48) and warped so.
  const auto dir = scratchDir("cli_tiff_orientation");
  writeBytes(dir / "scan.tif", orientedTiff(quadrantPicture(48, 32), 6));
  writeText(dir / "cage.json", R"({"version": 1, "points": [[4,4],[28,4],[28,28],[4,28]], "closed": true})");
  CliResult r = runCli("bind --cage cage.json --image scan.tif -o s.kcw.json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(dir / "s.kcw.json"));
  EXPECT_EQ(j["image_size"], nlohmann::json::parse("[32, 48]"));
  r = runCli("warp --session s.kcw.json -o upright.png", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Image upright = app::loadImage((dir / "upright.png").string());
  EXPECT_EQ(upright.width, 32);
  EXPECT_EQ(quadrantLayout(upright), "BRWG");
}

}  // namespace
}  // namespace kc::test
