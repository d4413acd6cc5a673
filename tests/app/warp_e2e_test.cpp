// End-to-end checks of `kcwarp-cli warp` and `demo` on the bundled examples: the warped image
// against OpenCV's warpAffine (linear precision in image space), the rest pose, locality, heatmaps
// and bad input (exit code 2 with a message naming the file).

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct CliRun {
  int code = -1;
  std::string out, err;
};

std::string slurpFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Runs kcwarp-cli with `args` in folder `dir`.
CliRun cli(const std::string& args, const fs::path& dir) {
  const std::string cmd = "cd '" + dir.string() + "' && '" + KC_CLI_PATH + "' " + args + " > out.txt 2> err.txt";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurpFile(dir / "out.txt");
  r.err = slurpFile(dir / "err.txt");
  return r;
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("kc_warp_e2e_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string example(const std::string& file) { return std::string(KC_SOURCE_DIR) + "/images/" + file; }

std::vector<Eigen::Vector2d> cagePoints(const std::string& name) {
  const json j = json::parse(slurpFile(example(name + ".cage.json")));
  std::vector<Eigen::Vector2d> c;
  for (const auto& p : j["points"]) c.emplace_back(p[0].get<double>(), p[1].get<double>());
  return c;
}

void writePositions(const fs::path& path, const std::vector<Eigen::Vector2d>& P) {
  json pts = json::array();
  for (const auto& p : P) pts.push_back({p.x(), p.y()});
  std::ofstream(path) << json{{"version", 1}, {"positions", pts}}.dump();
}

/// The session of example `name`: under ctest the fixture bound it once for the whole suite
/// (KC_BOUND_EXAMPLES, see tests/CMakeLists.txt); run by hand, it is bound once per process.
fs::path boundSession(const std::string& name) {
  if (const char* shared = std::getenv("KC_BOUND_EXAMPLES")) {
    const fs::path s = fs::path(shared) / (name + ".kcw.json");
    EXPECT_TRUE(fs::exists(s)) << s << " is missing: the bind_example_" << name << " fixture failed";
    return s;
  }
  static const fs::path dir = scratch("sessions_" + std::to_string(::getpid()));  // one per process
  const fs::path s = dir / (name + ".kcw.json");
  if (!fs::exists(s)) {
    const CliRun r = cli("bind --cage '" + example(name + ".cage.json") + "' --image '" + example(name + ".png") +
                          "' -o " + name + ".kcw.json",
                      dir);
    EXPECT_EQ(r.code, 0) << r.err;
  }
  return s;
}

/// A picture kcwarp wrote, as BGRA (kcwarp writes RGBA; any other kind is converted).
cv::Mat readBgra(const fs::path& file) {
  cv::Mat m = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  if (m.channels() == 3) cv::cvtColor(m, m, cv::COLOR_BGR2BGRA);
  return m;
}

/// PSNR over the BGR channels of pixels where mask ≠ 0.
double psnr(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  double sum = 0;
  long n = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      if (!mask.at<std::uint8_t>(y, x)) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.at<cv::Vec4b>(y, x)[c]) - double(b.at<cv::Vec4b>(y, x)[c]);
        sum += d * d;
      }
      n += 3;
    }
  EXPECT_GT(n, 300) << "mask too small";
  return sum == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 / (sum / double(n)));
}

/// Warps example `name` with the affine map x ↦ A x + b applied to all control points and
/// compares the result with cv::warpAffine inside the deformed cage (shrunk by 3 px).
double affineCase(const std::string& name, const Eigen::Matrix2d& A, const Eigen::Vector2d& b, const std::string& tag) {
  const fs::path dir = scratch("affine_" + name + "_" + tag);
  std::vector<Eigen::Vector2d> C = cagePoints(name), P;
  for (const auto& c : C) P.push_back(A * c + b);
  writePositions(dir / "pose.json", P);
  const CliRun r = cli("warp --session '" + boundSession(name).string() + "' --image '" + example(name + ".png") +
                        "' --pose pose.json -o out.png",
                    dir);
  EXPECT_EQ(r.code, 0) << r.err;
  const cv::Mat src = cv::imread(example(name + ".png"), cv::IMREAD_UNCHANGED);
  cv::Mat srcBgra;
  cv::cvtColor(src, srcBgra, cv::COLOR_BGR2BGRA);
  const cv::Mat M = (cv::Mat_<double>(2, 3) << A(0, 0), A(0, 1), b.x(), A(1, 0), A(1, 1), b.y());
  cv::Mat ref;
  cv::warpAffine(srcBgra, ref, M, src.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0, 0));
  const cv::Mat out = readBgra(dir / "out.png");
  EXPECT_EQ(out.size(), src.size());
  cv::Mat mask(src.size(), CV_8U, cv::Scalar(0));
  std::vector<cv::Point> poly;
  for (const auto& p : P) poly.emplace_back(int(std::lround(p.x())), int(std::lround(p.y())));
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(255));
  cv::erode(mask, mask, cv::getStructuringElement(cv::MORPH_ELLIPSE, {7, 7}));
  // Only where the reference is defined (the source image covers it).
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (ref.at<cv::Vec4b>(y, x)[3] < 255) mask.at<std::uint8_t>(y, x) = 0;
  const double value = psnr(out, ref, mask);
  std::printf("  %s %s: PSNR %.1f dB vs cv::warpAffine\n", name.c_str(), tag.c_str(), value);
  return value;
}

TEST(WarpCli, RestPoseReproducesTheImage) {
  for (const std::string name : {"checker", "star", "figure"}) {
    const fs::path dir = scratch("rest_" + name);
    const std::vector<Eigen::Vector2d> C = cagePoints(name);
    writePositions(dir / "pose.json", C);
    const CliRun r = cli("warp --session '" + boundSession(name).string() + "' --image '" + example(name + ".png") +
                          "' --pose pose.json -o out.png",
                      dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const cv::Mat src = cv::imread(example(name + ".png"), cv::IMREAD_UNCHANGED);
    cv::Mat srcBgra;
    cv::cvtColor(src, srcBgra, cv::COLOR_BGR2BGRA);
    const cv::Mat out = readBgra(dir / "out.png");
    cv::Mat covered;
    cv::extractChannel(out, covered, 3);
    EXPECT_GT(cv::countNonZero(covered), out.rows * out.cols * 99 / 100) << name;
    const double value = psnr(out, srcBgra, covered);
    std::printf("  %s rest pose: PSNR %.1f dB\n", name.c_str(), value);
    EXPECT_GE(value, 45.0) << name;
  }
}

TEST(WarpCli, AffinePoseGivesTheAffineWarp) {
  Eigen::Matrix2d A;
  A << 0.9, 0.15, -0.1, 1.05;
  EXPECT_GE(affineCase("checker", A, {12, -6}, "affine"), 35.0);
  EXPECT_GE(affineCase("star", A, {12, -6}, "affine"), 35.0);
  EXPECT_GE(affineCase("figure", A, {12, -6}, "affine"), 35.0);
}

TEST(WarpCli, TranslationAndRigidRotation) {
  EXPECT_GE(affineCase("star", Eigen::Matrix2d::Identity(), {9.5, -4.25}, "translate"), 35.0);
  const double t = 0.3;
  Eigen::Matrix2d R;
  R << std::cos(t), std::sin(t), -std::sin(t), std::cos(t);
  const Eigen::Vector2d o(160, 160);
  EXPECT_GE(affineCase("star", R, o - R * o, "rotate"), 35.0);
  EXPECT_GE(affineCase("checker", R, Eigen::Vector2d(128, 128) - R * Eigen::Vector2d(128, 128), "rotate"), 35.0);
}

TEST(WarpCli, MovingOneStarTipLeavesTheFarLegsUnchanged) {
  // Star control points: 0 top tip, 2 right, 4 bottom-right, 6 bottom-left, 8 left (odd: inner).
  const fs::path dir = scratch("locality");
  std::vector<Eigen::Vector2d> P = cagePoints("star");
  P[0] += Eigen::Vector2d(25, -10);
  writePositions(dir / "pose.json", P);
  const CliRun r = cli("warp --session '" + boundSession("star").string() + "' --image '" + example("star.png") +
                        "' --pose pose.json -o out.png",
                    dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat src = cv::imread(example("star.png"), cv::IMREAD_UNCHANGED);
  cv::Mat srcBgra;
  cv::cvtColor(src, srcBgra, cv::COLOR_BGR2BGRA);
  const cv::Mat out = readBgra(dir / "out.png");
  const std::vector<Eigen::Vector2d> C = cagePoints("star");
  for (int leg : {4, 6}) {  // a disc around the far leg's tip
    cv::Mat mask(src.size(), CV_8U, cv::Scalar(0));
    const Eigen::Vector2d tip = 0.8 * C[std::size_t(leg)] + 0.2 * Eigen::Vector2d(160, 168);
    cv::circle(mask, cv::Point(int(tip.x()), int(tip.y())), 22, cv::Scalar(255), cv::FILLED);
    EXPECT_GE(psnr(out, srcBgra, mask), 35.0) << "leg " << leg;
  }
  // ... while the moved tip's leg did change.
  cv::Mat mask(src.size(), CV_8U, cv::Scalar(0));
  const Eigen::Vector2d tip = 0.8 * C[0] + 0.2 * Eigen::Vector2d(160, 168);
  cv::circle(mask, cv::Point(int(tip.x()), int(tip.y())), 22, cv::Scalar(255), cv::FILLED);
  EXPECT_LT(psnr(out, srcBgra, mask), 30.0);
}

TEST(WarpCli, HeatmapOverlayAndOutsideModes) {
  const fs::path dir = scratch("heatmap");
  const std::string base = "warp --session '" + boundSession("star").string() + "' --image '" + example("star.png") +
                           "' --pose '" + example("star.pose.json") + "'";
  CliRun r = cli(base + " --heatmap 4 --out w4.png --scale log", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat heat = cv::imread((dir / "w4.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(heat.rows, 320);
  EXPECT_GT(heat.cols, 320);  // colour bar
  r = cli(base + " -o t.png --outside transparent --supersample --overlay --mesh-spacing 3", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("flipped triangles"), std::string::npos) << r.out;
  const cv::Mat t = readBgra(dir / "t.png");
  EXPECT_EQ(t.at<cv::Vec4b>(2, 2)[3], 0);       // outside the cage: transparent
  EXPECT_EQ(t.at<cv::Vec4b>(168, 160)[3], 255);  // the star's centre
  r = cli(base + " -o f.png --outside fixed", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat f = readBgra(dir / "f.png");
  const cv::Mat src = cv::imread(example("star.png"), cv::IMREAD_UNCHANGED);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(f.at<cv::Vec4b>(3, 3)[c], src.at<cv::Vec4b>(3, 3)[c]);
  // The default is pinned: the image corners stay, and the CLI says so.
  r = cli(base + " -o p.png", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("outside pinned"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("corners moved 0.00 px"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pinned exterior:"), std::string::npos) << r.out;
  // The bundled star's session samples a band around the cage (the default): deform is refused
  // with the fix named, and nothing is written.
  ASSERT_NE(slurpFile(boundSession("star")).find("\"exterior\":\"band\""), std::string::npos);
  r = cli(base + " -o band.png --outside deform", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--exterior frame"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "band.png"));
  // A session sampled over the whole picture that remembers "outside": "deform" is warped that
  // way unless --outside says otherwise.
  r = cli("bind --cage '" + example("star.cage.json") + "' --image '" + example("star.png") +
              "' --exterior frame -o frame.kcw.json",
          dir);
  ASSERT_EQ(r.code, 0) << r.err;
  json j = json::parse(slurpFile(dir / "frame.kcw.json"));
  EXPECT_EQ(j["params"]["exterior"], "frame");
  j["outside"] = "deform";
  std::ofstream(dir / "deform.kcw.json") << j.dump();
  const std::string viaSession = "warp --session deform.kcw.json --image '" + example("star.png") + "' --pose '" +
                                 example("star.pose.json") + "'";
  r = cli(viaSession + " -o d.png", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("outside deform"), std::string::npos) << r.out;
  r = cli(viaSession + " -o d2.png --outside pinned", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("outside pinned"), std::string::npos) << r.out;
  j["outside"] = "around";
  std::ofstream(dir / "bad.kcw.json") << j.dump();
  r = cli("warp --session bad.kcw.json -o b.png", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("outside must be one of"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "b.png"));
}

TEST(WarpCli, BadInputExitsWithTwoAndNamesTheProblem) {
  const fs::path dir = scratch("bad");
  const std::string session = boundSession("checker").string();
  const std::string img = " --image '" + example("checker.png") + "'";
  std::ofstream(dir / "three.json") << R"({"version":1,"handles":[{"translate":[1,2],"rotate":0},
      {"translate":[1,2],"rotate":0},{"translate":[1,2],"rotate":0}]})";
  CliRun r = cli("warp --session '" + session + "'" + img + " --pose three.json -o o.png", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("three.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o.png"));

  std::ofstream(dir / "nan.json") << R"({"version":1,"positions":[[0,0],[NaN,0],[255,255],[0,255]]})";
  r = cli("warp --session '" + session + "'" + img + " --pose nan.json -o o.png", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("nan.json"), std::string::npos) << r.err;

  std::ofstream(dir / "huge.json") << R"({"version":1,"positions":[[0,0],[1e999,0],[255,255],[0,255]]})";
  r = cli("warp --session '" + session + "'" + img + " --pose huge.json -o o.png", dir);
  EXPECT_EQ(r.code, 2) << r.err;

  r = cli("warp --session '" + session + "' --image missing.png --pose '" + example("checker.pose.json") + "' -o o.png",
          dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("missing.png"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;

  r = cli("warp --session '" + session + "' --image '" + example("star.png") + "' -o o.png", dir);  // wrong size
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("320x320"), std::string::npos) << r.err;

  r = cli("warp --session '" + session + "'" + img + " -o o.png --outside sideways", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--outside"), std::string::npos) << r.err;

  r = cli("warp --session '" + session + "'" + img + " --heatmap 9 --out h.png", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_FALSE(fs::exists(dir / "o.png"));
}

TEST(DemoCli, WritesWarpedImagesHeatmapsAndReport) {
  const fs::path dir = scratch("demo");
  const CliRun r = cli("demo --out demo --images '" + std::string(KC_SOURCE_DIR) + "/images'", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const std::string name : {"checker", "star", "figure", "stick"})
    for (const std::string kind : {".warped.png", ".overlay.png", ".heatmap.png", ".heatmap-log.png", ".kcw.json"})
      EXPECT_TRUE(fs::exists(dir / "demo" / (name + kind))) << name + kind;
  const std::string report = slurpFile(dir / "demo" / "report.txt");
  EXPECT_NE(report.find("partition of unity"), std::string::npos);
  EXPECT_NE(report.find("flipped triangles"), std::string::npos);
  // LBC next to KC for every example with a closed cage (not the stick figure): solver report,
  // locality and objective.
  EXPECT_NE(report.find("LBC is not run on this example"), std::string::npos) << report;
  for (const std::string name : {"checker", "star", "figure"})
    EXPECT_TRUE(fs::exists(dir / "demo" / (name + ".lbc.heatmap-log.png"))) << name;
  std::size_t lbcSections = 0;
  for (std::size_t at = report.find("-- LBC"); at != std::string::npos; at = report.find("-- LBC", at + 1)) ++lbcSections;
  EXPECT_EQ(lbcSections, 3u) << report;
  EXPECT_NE(report.find("solver: LBC on"), std::string::npos);
  EXPECT_NE(report.find("P(1e-3)"), std::string::npos);
  EXPECT_NE(report.find("objective (LBC eq. 14)"), std::string::npos);
  // The figure's structure lines (images/figure.structure.json): the side-by-side warp, and each
  // line straight with them (under the pose's translations) where it bends without them.
  EXPECT_TRUE(fs::exists(dir / "demo" / "figure.structure.png"));
  ASSERT_NE(report.find("structure: 2 lines"), std::string::npos) << report;
  std::size_t lines = 0;
  for (std::size_t at = report.find("bend without / with the lines "); at != std::string::npos;
       at = report.find("bend without / with the lines ", at + 1), ++lines) {
    double without = -1.0, with = -1.0;
    ASSERT_EQ(std::sscanf(report.c_str() + at, "bend without / with the lines %lf / %lf px", &without, &with), 2);
    EXPECT_LT(with, 0.01) << report.substr(at, 120);
    EXPECT_GT(without, 0.1) << report.substr(at, 120);
  }
  EXPECT_EQ(lines, 2u);
}

}  // namespace
