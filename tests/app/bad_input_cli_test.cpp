// Hostile and careless inputs, one row each, through the real kcwarp-cli: every
// one must exit 2 with one line on stderr naming the problem, without a crash, a hang, a damaged
// file or a partial output. The table prints each case's exit code and wall time.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bad_files.h"
#include "cli_run.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"

namespace kc::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Timed {
  CliResult r;
  double seconds = 0.0;
};

/// kcwarp-cli under `timeout` (a hang fails the case instead of the suite), in `dir`.
Timed runTimed(const std::string& args, const fs::path& dir) {
  const auto out = dir / "cli.stdout", err = dir / "cli.stderr";
  const std::string cmd = "cd '" + dir.string() + "' && timeout -k 5 60 '" + std::string(KC_CLI_PATH) + "' " + args + " > '" +
                          out.string() + "' 2> '" + err.string() + "' < /dev/null";
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(cmd.c_str());
  Timed t;
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t.r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  t.r.out = slurp(out);
  t.r.err = slurp(err);
  return t;
}

/// A closed polygon approximating a circle of n points.
std::string circleCage(int n, double cx, double cy, double r) {
  json pts = json::array();
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * 3.141592653589793 * i / n;
    pts.push_back({cx + r * std::cos(t), cy + r * std::sin(t)});
  }
  return json{{"version", 1}, {"points", pts}, {"closed", true}}.dump();
}

/// A closed spiral strip: `turns` turns whose walls are `gap` pixels apart.
std::string spiralCage(double cx, double cy, double gap, int turns) {
  json outer = json::array(), inner = json::array();
  const int perTurn = 48;
  for (int k = 0; k <= turns * perTurn; ++k) {
    const double t = 2.0 * 3.141592653589793 * k / perTurn;
    const double r = 10.0 + 2.0 * gap * t / (2.0 * 3.141592653589793);
    outer.push_back({cx + (r + gap) * std::cos(t), cy + (r + gap) * std::sin(t)});
    inner.push_back({cx + r * std::cos(t), cy + r * std::sin(t)});
  }
  json pts = outer;
  for (auto it = inner.rbegin(); it != inner.rend(); ++it) pts.push_back(*it);
  return json{{"version", 1}, {"points", pts}, {"closed", true}}.dump();
}

class BadInput : public ::testing::Test {
 protected:
  /// One bound session shared by the cases that corrupt it.
  static void SetUpTestSuite() {
    s_dir = scratchDir("bad_input_shared");
    writeText(s_dir / "cage.json", kSquare);
    const CliResult r = runCli("bind --cage cage.json --size 96,96 --spacing 8 -o s.kcw.json", s_dir);
    ASSERT_EQ(r.code, 0) << r.err;
    s_session = json::parse(slurp(s_dir / "s.kcw.json"));
  }
  static json session() { return s_session; }

  void SetUp() override {
    // A failure in SetUpTestSuite only skips the cases; make it fail each of them instead.
    ASSERT_FALSE(s_session.is_null()) << "the shared bind in " << s_dir << " failed";
    m_dir = scratchDir(std::string("bad_input_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    writeText(m_dir / "cage.json", kSquare);
    fs::copy_file(s_dir / "s.kcw.json", m_dir / "s.kcw.json");
  }

  /// Runs the case and checks the contract: exit 2, exactly one line on stderr containing
  /// `message`; prints the row of the table.
  void expectRefused(const std::string& args, const std::string& message) {
    const Timed t = runTimed(args, m_dir);
    std::printf("[case] %-44s exit %d  %6.2f s  %s", ::testing::UnitTest::GetInstance()->current_test_info()->name(), t.r.code,
                t.seconds, t.r.err.c_str());
    EXPECT_EQ(t.r.code, 2) << args << "\nstderr: " << t.r.err << "\nstdout: " << t.r.out;
    EXPECT_EQ(lineCount(t.r.err), 1) << t.r.err;
    EXPECT_TRUE(contains(t.r.err, message)) << "expected '" << message << "' in: " << t.r.err;
  }
  void writeSession(const json& j) { writeText(m_dir / "bad.kcw.json", j.dump()); }

  fs::path m_dir;
  static inline fs::path s_dir;
  static inline json s_session;
};

// ---- Numbers from files are range-checked before conversion --------------------------------

TEST_F(BadInput, SessionImageSizeBeyondInt) {
  json j = session();
  j["image_size"] = {4294967552ull, 256};
  writeSession(j);
  expectRefused("stats --session bad.kcw.json", "image_size[0] = 4294967552 is out of range");
}

TEST_F(BadInput, SessionImageSizeIntMax) {
  json j = session();
  j["image_size"] = {2147483647, 256};
  writeSession(j);
  expectRefused("stats --session bad.kcw.json", "image_size[0]");
}

TEST_F(BadInput, SessionImageSizeTooManyPixels) {
  json j = session();
  j["image_size"] = {20000, 20000};
  writeSession(j);
  expectRefused("warp --session bad.kcw.json --heatmap 0 --out h.png", "megapixels");
  EXPECT_FALSE(fs::exists(m_dir / "h.png"));
}

TEST_F(BadInput, SessionImageSideTooLong) {
  json j = session();
  j["image_size"] = {40000, 40000};
  writeSession(j);
  expectRefused("warp --session bad.kcw.json --heatmap 0 --out h.png", "image_size[0] = 40000 is out of range");
}

TEST_F(BadInput, SessionHugeWeight) {
  json j = json::parse(app::sessionToJson(app::sessionFromJson(session().dump(), "s.kcw.json"), app::WeightsForm::Rows));
  j["weights"]["optimized"][5][1] = 1e308;
  writeSession(j);
  expectRefused("stats --session bad.kcw.json --json", "weights.optimized[5][1] = 1e+308 is out of range");
}

TEST_F(BadInput, SessionCompactWeightsCorrupt) {
  json j = session();
  std::string& text = j["weights"]["optimized_b64"]["base64"].get_ref<std::string&>();
  text[text.size() / 2] = '*';
  writeSession(j);
  expectRefused("stats --session bad.kcw.json", "weights.optimized_b64.base64 is not valid base64: character");
  j = session();
  std::string& cut = j["weights"]["initial_b64"]["base64"].get_ref<std::string&>();
  cut.resize(cut.size() / 2 / 4 * 4);
  writeSession(j);
  expectRefused("warp --session bad.kcw.json --heatmap 0 --out h.png", "weights.initial_b64.base64 has");
  EXPECT_FALSE(fs::exists(m_dir / "h.png"));
}

TEST_F(BadInput, SessionEdgeEndWraps) {
  json j = session();
  const auto& kinds = j["samples"]["kinds"];
  std::size_t edge = 0;
  while (kinds[edge] != "edge") ++edge;
  j["samples"]["edge_ends"][edge] = {4294967298ull, 1};
  writeSession(j);
  expectRefused("stats --session bad.kcw.json", "edge_ends[" + std::to_string(edge) + "][0] = 4294967298 is out of range");
}

TEST_F(BadInput, SessionHeatIterationsHuge) {
  json j = session();
  j["params"]["heat_iterations"] = 1000000000000ll;
  writeSession(j);
  expectRefused("stats --session bad.kcw.json", "params.heat_iterations");
}

TEST_F(BadInput, SessionSigmaFarTooWide) {
  json j = session();
  j["params"]["sigma"] = 1e6;
  if (j.contains("field") && j["field"].contains("sigma")) j["field"]["sigma"] = 1e6;
  writeSession(j);
  expectRefused("stats --session bad.kcw.json", "sigma");
}

TEST_F(BadInput, APictureOrBinaryFileGivenAsJsonIsNamedAsSuch) {
  fs::copy_file(fs::path(KC_SOURCE_DIR) / "images" / "star.png", m_dir / "star.png");
  expectRefused("stats --session star.png", "star.png: this file is a PNG image, not JSON text");
  expectRefused("bind --cage star.png --size 96,96 -o out.kcw.json", "star.png: this file is a PNG image, not JSON text");
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
  fs::copy_file(fs::path(KC_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / "image_header" / "seed.jpg", m_dir / "photo.json");
  expectRefused("warp --session s.kcw.json --pose photo.json -o W.png --image none.png", "photo.json: this file is a JPEG image");
  writeText(m_dir / "bmw.json", "BMW 320i: not JSON, not a picture");  // a picture's signature alone does not make one
  expectRefused("bind --cage bmw.json --size 96,96 -o out.kcw.json", "bmw.json: malformed JSON at byte 0");
  writeText(m_dir / "zeros.json", std::string("{\"version\": 1,\0\0\0", 16));
  expectRefused("bind --cage zeros.json --size 96,96 -o out.kcw.json", "zeros.json: this file is binary data, not JSON text");
  EXPECT_FALSE(fs::exists(m_dir / "W.png"));
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
}

TEST_F(BadInput, ABadStructureFileStopsTheBindBeforeItPrintsAnything) {
  // A cage large enough that the spacing is automatic and worth a line of its own on a good bind.
  writeText(m_dir / "big.json", R"({"version": 1, "points": [[100,100],[3900,100],[3900,3900],[100,3900]], "closed": true})");
  writeText(m_dir / "lines.json", R"({"version": 1, "lines": [[[500, 500], [2000, )");
  const Timed good = runTimed("bind --cage big.json --size 4000,4000 -o good.kcw.json", m_dir);
  ASSERT_EQ(good.r.code, 0) << good.r.err;
  ASSERT_TRUE(contains(good.r.out, "spacing: automatic")) << good.r.out;
  expectRefused("bind --cage big.json --size 4000,4000 --structure lines.json -o out.kcw.json", "lines.json: malformed JSON");
  const Timed bad = runTimed("bind --cage big.json --size 4000,4000 --structure lines.json -o out.kcw.json", m_dir);
  EXPECT_EQ(bad.r.out, "") << "stdout of a refused bind";
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
}

TEST_F(BadInput, SessionNanLiteral) {
  std::string text = session().dump();
  const std::string key = "\"sigma\":";
  const auto at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  text.replace(at + key.size(), text.find(',', at) - at - key.size(), "NaN");
  writeText(m_dir / "bad.kcw.json", text);
  expectRefused("stats --session bad.kcw.json", "malformed JSON");
}

TEST_F(BadInput, CageEdgeIndexWraps) {
  writeText(m_dir / "edges.json",
            R"({"version":1,"points":[[10,10],[50,10],[50,50],[10,50]],"closed":true,"edges":[[0,1],[1,2],[2,4294967298],[3,0]]})");
  expectRefused("bind --cage edges.json --size 64,64 -o out.kcw.json", "edges[2][1] = 4294967298 is out of range");
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
}

// A stick figure (a loop for the head, open sticks; thesis 6.2.2) with a bad edge list.
TEST_F(BadInput, StickGraphWithBadEdges) {
  const std::string points = R"("points":[[40,10],[60,10],[60,30],[40,30],[60,50],[20,60],[100,60],[60,90]],"closed":false)";
  const std::string head = "[0,1],[1,2],[2,3],[3,0]";
  writeText(m_dir / "dangling.json", "{\"version\":1," + points + R"(,"edges":[)" + head + ",[2,4],[4,9]]}");
  expectRefused("bind --cage dangling.json --size 120,120 -o out.kcw.json", "dangling.json: edges[5][1] = 9 is out of range");
  writeText(m_dir / "repeated.json", "{\"version\":1," + points + R"(,"edges":[)" + head + ",[2,4],[4,7],[7,4]]}");
  expectRefused("bind --cage repeated.json --size 120,120 -o out.kcw.json", "repeated.json: cage edges 5 and 6 are the same edge");
  writeText(m_dir / "crossing.json", "{\"version\":1," + points + R"(,"edges":[)" + head + ",[2,4],[4,7],[5,6]]}");
  expectRefused("bind --cage crossing.json --size 120,120 -o out.kcw.json", "crossing.json: cage is self-intersecting: edge 5");
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
}

TEST_F(BadInput, CageCoordinateTooLarge) {
  writeText(m_dir / "far.json", R"({"version":1,"points":[[10,10],[1e300,10],[50,50]],"closed":true})");
  expectRefused("bind --cage far.json --size 64,64 -o out.kcw.json", "points[1][0] = 1e+300 is out of range");
}

TEST_F(BadInput, EvalNanFirstRowIsNotAHeader) {
  writeText(m_dir / "p.csv", "10,nan\n20,20\n30,30\n");
  expectRefused("eval --session s.kcw.json --points p.csv -o w.csv", "line 1");
  EXPECT_FALSE(fs::exists(m_dir / "w.csv"));
}

TEST_F(BadInput, BindLocalityNan) {
  expectRefused("bind --cage cage.json --size 96,96 --locality nan -o out.kcw.json", "--locality");
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
}

TEST_F(BadInput, BindLocalityInf) { expectRefused("bind --cage cage.json --size 96,96 --locality inf -o out.kcw.json", "--locality"); }

TEST_F(BadInput, BindLocalitySpacingsNanOrNegative) {
  expectRefused("bind --cage cage.json --size 96,96 --locality-spacings nan -o out.kcw.json",
                "--locality-spacings: must be 0 (off) or a positive number of spacings");
  expectRefused("bind --cage cage.json --size 96,96 --locality-spacings -1 -o out.kcw.json", "--locality-spacings: must be 0 (off)");
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
}

TEST_F(BadInput, BindTargetFloorOutOfRange) {
  for (const char* floor : {"nan", "-0.1", "0.5"})
    expectRefused(std::string("bind --cage cage.json --size 96,96 --target-floor ") + floor + " -o out.kcw.json",
                  "--target-floor: must be in [0, 0.5)");
  EXPECT_FALSE(fs::exists(m_dir / "out.kcw.json"));
}

TEST_F(BadInput, BindHeatIterationsHuge) {
  expectRefused("bind --cage cage.json --size 96,96 --heat-iterations 100000000 -o out.kcw.json", "--heat-iterations");
}

// ---- Bounded work -----------------------------------------------------------------------------

TEST_F(BadInput, CageFromDevZero) { expectRefused("bind --cage /dev/zero --size 96,96 -o out.kcw.json", "not a regular file"); }

TEST_F(BadInput, SessionFromDevZero) { expectRefused("stats --session /dev/zero", "not a regular file"); }

TEST_F(BadInput, PointsFromDevZero) {
  expectRefused("eval --session s.kcw.json --points /dev/zero -o w.csv", "not a regular file");
}

TEST_F(BadInput, SessionFromFifoWithoutWriter) {
  ASSERT_EQ(::mkfifo((m_dir / "fifo").c_str(), 0600), 0);
  expectRefused("stats --session fifo", "not a regular file");
}

TEST_F(BadInput, CageFileTooLarge) {
  writeText(m_dir / "big.json", "{");
  fs::resize_file(m_dir / "big.json", 17u << 20);  // sparse: costs no disk
  expectRefused("bind --cage big.json --size 96,96 -o out.kcw.json", "more than the 16 MiB");
}

TEST_F(BadInput, PngHeaderClaims60000Squared) {
  const std::string png = pngClaiming(60000, 60000);
  writeText(m_dir / "huge.png", png);
  EXPECT_LT(png.size(), 600u);
  expectRefused("bind --cage cage.json --image huge.png -o out.kcw.json", "above kcwarp's limit");
}

TEST_F(BadInput, PngHeaderClaims20000Squared) {
  writeText(m_dir / "big.png", pngClaiming(20000, 20000));
  expectRefused("sample --cage cage.json --image big.png -o s.json", "is 400 megapixels, above kcwarp's limit of 67108864 pixels");
  EXPECT_FALSE(fs::exists(m_dir / "s.json"));
}

TEST_F(BadInput, ImageThatIsNotAnImage) {
  writeText(m_dir / "text.png", "just text, not a picture\n");
  expectRefused("bind --cage cage.json --image text.png -o out.kcw.json", "not an image kcwarp reads");
}

TEST_F(BadInput, TruncatedPnmGivesOneLineWithTheDecodersReason) {  // OpenCV writes its reason to std::cerr
  writeText(m_dir / "cut.ppm", std::string("P6\n64 64\n255\n") + std::string(100, 'x'));
  expectRefused("sample --cage cage.json --image cut.ppm -o s.json", "cut.ppm: cannot decode the PNM image (corrupt or truncated): ");
  EXPECT_FALSE(fs::exists(m_dir / "s.json"));
}

TEST_F(BadInput, BindSpacingTooFine) {
  expectRefused("bind --cage cage.json --size 256,256 --spacing 0.5 --exterior frame -o out.kcw.json", "use --spacing");
}

TEST_F(BadInput, BindSigmaTooWide) {
  expectRefused("bind --cage cage.json --size 512,512 --spacing 2 --sigma 300 --exterior frame -o out.kcw.json", "--sigma 0");
}

TEST_F(BadInput, BindSpiralAtHalfPixel) {
  writeText(m_dir / "spiral.json", spiralCage(128, 128, 4.0, 8));
  expectRefused("bind --cage spiral.json --size 256,256 --spacing 0.5 --exterior frame -o out.kcw.json", "use --spacing");
}

TEST_F(BadInput, CageWithFortyThousandPoints) {
  writeText(m_dir / "circle.json", circleCage(40000, 500, 500, 400));
  // Its points are 0.063 px apart: a graded bind refuses that before estimating its cost.
  expectRefused("bind --cage circle.json --size 1000,1000 -o out.kcw.json", "0.0628 px apart, narrower than");
}

TEST_F(BadInput, WarpMeshTooFine) {
  json j = session();
  j["image_size"] = {8000, 8000};
  writeSession(j);
  expectRefused("warp --session bad.kcw.json --mesh-spacing 0.5 -o W.png --image none.png", "--mesh-spacing");
  EXPECT_FALSE(fs::exists(m_dir / "W.png"));
}

// ---- Cages finer than the sampling: refused with the place and what to change ---------------

TEST_F(BadInput, CageWithHundredthPixelEdge) {
  writeText(m_dir / "pent.json", R"({"version":1,"points":[[16,16],[80,16],[80,80],[16,80],[16,79.99]],"closed":true})");
  expectRefused("bind --cage pent.json --size 96,96 -o out.kcw.json", "cage points 3 and 4 are 0.01 px apart");
}

TEST_F(BadInput, ThinQuad) {
  // A graded bind refines a 0.5 px sliver; one of 0.05 px is narrower than kcwarp resolves (0.1 px).
  writeText(m_dir / "thin.json", R"({"version":1,"points":[[10,40],[90,40],[90,40.05],[10,40.05]],"closed":true})");
  expectRefused("bind --cage thin.json --size 96,96 -o out.kcw.json", "0.05 px apart, narrower than the 0.1 px kcwarp resolves");
  writeText(m_dir / "wide.json", R"({"version":1,"points":[[10,40],[90,40],[90,40.5],[10,40.5]],"closed":true})");
  expectRefused("bind --cage wide.json --size 96,96 --uniform-spacing -o out.kcw.json", "0.5 px apart");
}

TEST_F(BadInput, SpiralWithGapsNarrowerThanTheSpacing) {
  writeText(m_dir / "spiral.json", spiralCage(128, 128, 4.0, 3));
  expectRefused("bind --cage spiral.json --size 256,256 --spacing 6 --uniform-spacing -o out.kcw.json", "use --spacing");
}

// ---- Outputs: nothing written by a failing command; special files never replaced ---------------

TEST_F(BadInput, OutputIsAFifo) {
  ASSERT_EQ(::mkfifo((m_dir / "out.fifo").c_str(), 0600), 0);
  expectRefused("bind --cage cage.json --size 96,96 --spacing 8 -o out.fifo", "not a regular file");
  struct stat st {};
  ASSERT_EQ(::lstat((m_dir / "out.fifo").c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

TEST_F(BadInput, OutputFolderMissing) {
  expectRefused("bind --cage cage.json --size 96,96 --spacing 8 -o missing/out.kcw.json", "does not exist");
}

TEST_F(BadInput, SampleWithPngInMissingFolder) {
  writeText(m_dir / "S.json", "previous content");
  expectRefused("sample --cage cage.json --size 96,96 --spacing 8 -o S.json --png missing-dir/p.png", "does not exist");
  EXPECT_EQ(slurp(m_dir / "S.json"), "previous content");
}

TEST_F(BadInput, WarpHeatmapWithBadPose) {
  writeText(m_dir / "pose.json", R"({"version":1,"positions":[[1,2)");
  expectRefused("warp --session s.kcw.json --heatmap 0 --out H.png -o W.png --pose pose.json --image none.png",
                "pose.json: malformed JSON");
  EXPECT_FALSE(fs::exists(m_dir / "H.png"));
  EXPECT_FALSE(fs::exists(m_dir / "W.png"));
}

TEST_F(BadInput, WarpHeatmapWithMissingImage) {
  expectRefused("warp --session s.kcw.json --heatmap 0 --out H.png -o W.png --image missing.png", "missing.png: no such file");
  EXPECT_FALSE(fs::exists(m_dir / "H.png"));
}

TEST_F(BadInput, WarpHeatmapWithPoseOfWrongSize) {
  writeText(m_dir / "pose.json", R"({"version":1,"positions":[[1,2]]})");
  writeText(m_dir / "img.png", pngClaiming(96, 96));
  expectRefused("warp --session s.kcw.json --heatmap 0 --out H.png -o W.png --pose pose.json --image img.png", "pose.json");
  EXPECT_FALSE(fs::exists(m_dir / "H.png"));
}

TEST_F(BadInput, DemoWithABrokenExampleWritesNothing) {
  fs::copy(fs::path(KC_SOURCE_DIR) / "images", m_dir / "examples");
  writeText(m_dir / "examples" / "figure.pose.json", R"({"version":1,"positions":[]})");
  expectRefused("demo --images examples --out demo-out", "figure.pose.json");
  EXPECT_FALSE(fs::exists(m_dir / "demo-out"));
}

// ---- Images decoded strictly, sessions checked for meaning, memory bounded up front ------------

TEST_F(BadInput, TruncatedJpeg) {
  Image picture(96, 96);
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      std::uint8_t* p = picture.pixel(x, y);
      p[0] = std::uint8_t(x * 2), p[1] = std::uint8_t(y * 2), p[2] = std::uint8_t((x ^ y) * 3), p[3] = 255;
    }
  app::saveImage((m_dir / "full.jpg").string(), picture);
  const std::string bytes = slurp(m_dir / "full.jpg");
  writeText(m_dir / "cut.jpg", bytes.substr(0, bytes.size() * 2 / 3));
  expectRefused("sample --cage cage.json --image cut.jpg -o s.json", "cut.jpg: cannot decode the JPEG image: ");
  EXPECT_FALSE(fs::exists(m_dir / "s.json"));
}

TEST_F(BadInput, PngTextChunkClaimingTwoGigabytes) {
  writeText(m_dir / "chunk.png", pngTextChunkClaiming(0x7ffffff0u));
  expectRefused("sample --cage cage.json --image chunk.png -o s.json", "a chunk claims 2147483632 bytes");
}

TEST_F(BadInput, SessionWeightsAllZero) {
  json j = session();
  json& block = j["weights"]["optimized_b64"];
  block["base64"] = base64OfZeroBytes(block["shape"][0].get<std::size_t>() * block["shape"][1].get<std::size_t>() * 8);
  writeSession(j);
  expectRefused("eval --session bad.kcw.json --points p.csv -o w.csv", "weights.optimized row 0 sums to 0 (partition of unity");
}

TEST_F(BadInput, SessionOfTheKernelBackendWithAMeshField) {
  json j = session();
  j["field"] = {{"kind", "mesh"}, {"vertices", j["cage"]["points"]}, {"triangles", {{0, 1, 2}, {0, 2, 3}}}};
  writeSession(j);
  expectRefused("stats --session bad.kcw.json", "field.kind \"mesh\" does not match params.backend \"kc\"");
}

TEST_F(BadInput, EvalOfMorePointsTimesControlsThanTheLimit) {
  std::string csv;
  csv.reserve(13'000'000 * 4);
  for (int i = 0; i < 13'000'000; ++i) csv += "1,1\n";  // 13 million points x 4 control points
  writeText(m_dir / "many.csv", csv);
  expectRefused("eval --session s.kcw.json --points many.csv -o w.csv", "above kcwarp's limit of 50000000 for one eval");
  EXPECT_FALSE(fs::exists(m_dir / "w.csv"));
}

TEST_F(BadInput, SessionOfTinyValuesBeyondTheParseLimit) {
  // 160 MB of one-digit numbers would parse into ~2.6 GB (16-byte values, arrays grown by
  // doubling): refused from a streaming count before anything is built.
  std::string text = R"({"version": 1, "cage": {"points": [[16,16],[80,16],[80,80],[16,80]]}, "junk": [)";
  text.reserve(text.size() + 160'000'010);
  for (int i = 0; i < 40'000'000; ++i) text += "0,0,";
  text += "0]}";
  writeText(m_dir / "huge.kcw.json", text);
  std::string().swap(text);
  expectRefused("stats --session huge.kcw.json", "parsing this file would need more than");
}

// ---- Options: seeds and thread counts that would wrap ----------------------------------------

TEST_F(BadInput, SeedOutOfRange) {
  expectRefused("sample --cage cage.json --size 96,96 --seed -1 -o s.json", "--seed");
  expectRefused("sample --cage cage.json --size 96,96 --seed 18446744073709551616 -o s.json", "--seed");
  EXPECT_FALSE(fs::exists(m_dir / "s.json"));
  expectRefused("bind --cage cage.json --size 96,96 --seed -1 -o b.kcw.json", "--seed");
  expectRefused("bind --cage cage.json --size 96,96 --seed 18446744073709551616 -o b.kcw.json", "--seed");
  EXPECT_FALSE(fs::exists(m_dir / "b.kcw.json"));
}

TEST_F(BadInput, BenchNegativeThreads) { expectRefused("bench --threads -3", "--threads"); }

TEST_F(BadInput, ArgumentsWithNewlinesGiveOneLine) {
  expectRefused("sample --cage 'cage\nfile\n.json' --size 96,96 -o s.json", "cage\\nfile\\n.json: no such file");
  expectRefused("warp --session s.kcw.json --outside 'a\nb\nc' -o w.png", "--outside");
  expectRefused("sample --cage cage.json --size 96,96 --seed '1\n2' -o s.json", "--seed");  // CLI11's own message
}

TEST_F(BadInput, OutputNameOfNameMaxLength) {
  const std::string name(250, 'n');
  for (int k = 0; k < 2; ++k) {  // new, then replaced
    const Timed t = runTimed("sample --cage cage.json --size 96,96 -o " + name + ".json", m_dir);
    EXPECT_EQ(t.r.code, 0) << t.r.err;
  }
  EXPECT_TRUE(fs::exists(m_dir / (name + ".json")));
}

// ---- Standard output: what a command prints is flushed and checked ---------------------------

/// kcwarp-cli `args` with standard output sent to `stdoutRedirect` (shell syntax, e.g.
/// "> /dev/full" or ">&-"); exit code and stderr.
CliResult runWithStdout(const std::string& args, const std::string& stdoutRedirect, const fs::path& dir) {
  const auto err = dir / "cli.stderr";
  const std::string cmd = "cd '" + dir.string() + "' && timeout -k 5 60 '" + std::string(KC_CLI_PATH) + "' " + args + " " +
                          stdoutRedirect + " 2> '" + err.string() + "' < /dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = slurp(err);
  return r;
}

TEST_F(BadInput, StandardOutputFullOrClosed) {
  for (const char* redirect : {"> /dev/full", ">&-"}) {
    const CliResult r = runWithStdout("stats --session s.kcw.json --json", redirect, m_dir);
    EXPECT_EQ(r.code, 2) << redirect << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_TRUE(contains(r.err, "standard output: cannot write")) << r.err;
  }
  // A command that writes a file with standard output closed: the file gets none of what it printed.
  const CliResult r = runWithStdout("bind --cage cage.json --size 96,96 --spacing 8 -o again.kcw.json", ">&-", m_dir);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NO_THROW(json::parse(slurp(m_dir / "again.kcw.json")));
  EXPECT_EQ(runWithStdout("stats --session s.kcw.json --json", "> out.json", m_dir).code, 0);
  EXPECT_NO_THROW(json::parse(slurp(m_dir / "out.json")));
}

// ---- Saves that succeed: mode kept, symlinks written through, no temporary file left ----------

TEST_F(BadInput, SaveKeepsModeFollowsSymlinkAndLeavesNoTemporary) {
  writeText(m_dir / "ro.kcw.json", "old");
  fs::permissions(m_dir / "ro.kcw.json", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  Timed t = runTimed("bind --cage cage.json --size 96,96 --spacing 8 -o ro.kcw.json", m_dir);
  ASSERT_EQ(t.r.code, 0) << t.r.err;
  EXPECT_EQ(fs::status(m_dir / "ro.kcw.json").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  EXPECT_NE(slurp(m_dir / "ro.kcw.json"), "old");

  fs::create_directory(m_dir / "real");
  writeText(m_dir / "real" / "target.kcw.json", "old");
  fs::create_symlink("real/target.kcw.json", m_dir / "link.kcw.json");
  t = runTimed("bind --cage cage.json --size 96,96 --spacing 8 -o link.kcw.json", m_dir);
  ASSERT_EQ(t.r.code, 0) << t.r.err;
  EXPECT_TRUE(fs::is_symlink(m_dir / "link.kcw.json"));
  EXPECT_TRUE(contains(slurp(m_dir / "real" / "target.kcw.json"), "\"weights\""));

  for (const auto& d : {m_dir, m_dir / "real"})
    for (const auto& e : fs::directory_iterator(d))
      EXPECT_FALSE(contains(e.path().filename().string(), ".tmp")) << "left behind: " << e.path();
}

}  // namespace
}  // namespace kc::test
