// Big pictures: cost against picture size. Generated photo-like pictures of 0.1, 1, 4
// and 12 megapixels (4:3) with the same 34-point cage shape over a quarter of each (its bounding
// box is half the width and half the height, centred), default bind parameters. Rows:
//   Bind        `kcwarp-cli bind` as a child process (process start to session file)
//   OneShotWarp `kcwarp-cli warp -o OUT.png` as a child process (process start to PNG)
//   SessionLoad app::loadSession of that session, in this process
//   Export      warp mesh + deform + render + PNG encode (default level) + atomic write, in process;
//               counters mesh_s, deform_s, render_s, encode_s, write_s split its time
//   PerPose     WarpMesh::deform of the export's mesh (DeformPass::Live, as the GUI while dragging)
//               along 20 poses from rest to the case's pose, in process; time per pose
//   Floor       OpenCV imread + one cv::remap + imwrite (default PNG level) of the same picture
// Counters: peak_MB is the child's peak resident memory (measured by /usr/bin/time), for the rows
// that run a child; samples / file_MB where they apply. Each row runs once (Iterations(1)): a bind of
// 12 MP takes minutes. Run one size with --benchmark_filter='/12$' etc.
#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <sys/wait.h>
#include <spawn.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/core/deform.h"
#include "mls_peer.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// One generated case (or the scaled figure): its folder holds picture.png, cage.json, pose.json, and after the bind row
/// session.kcw.json.
struct Case {
  int width = 0, height = 0;
  fs::path dir;
  bool bound = false;
};

int sizeForTenthsOfMegapixels(int tenths, bool width) {
  const double pixels = tenths * 1e5;
  const double w = std::round(std::sqrt(pixels * 4.0 / 3.0));
  return static_cast<int>(width ? w : std::round(pixels / w));
}

/// Smooth colour waves, a coarse checker and Gaussian noise (σ 4 grey levels): compresses like a photo.
void writePicture(const fs::path& path, int w, int h) {
  cv::Mat img(h, w, CV_8UC3);
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 4.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto& p = img.at<cv::Vec3b>(y, x);
      const double u = 4000.0 * x / w, v = 3000.0 * y / h;  // the same picture at every size
      p[2] = cv::saturate_cast<uchar>(128 + 90 * std::sin(u * 0.004) * std::cos(v * 0.003) + noise(rng));
      p[1] = cv::saturate_cast<uchar>(128 + 80 * std::sin((u + v) * 0.002) + noise(rng));
      p[0] = cv::saturate_cast<uchar>(((int(u) / 250 + int(v) / 250) % 2 ? 200 : 60) + noise(rng));
    }
  cv::imwrite(path.string(), img, {cv::IMWRITE_PNG_COMPRESSION, 1});
}

/// 34 points on r(θ) = 1 + 0.15 sin 3θ, scaled to a box of half the picture's width and height.
void writeCageAndPose(const Case& c) {
  std::string cage = R"({"version": 1, "closed": true, "points": [)", pose = R"({"version": 1, "positions": [)";
  const double cx = c.width / 2.0, cy = c.height / 2.0, rx = c.width / 4.0 / 1.15, ry = c.height / 4.0 / 1.15;
  for (int i = 0; i < 34; ++i) {
    const double t = 2 * M_PI * i / 34, r = 1 + 0.15 * std::sin(3 * t);
    const double x = cx + rx * r * std::cos(t), y = cy + ry * r * std::sin(t);
    // The pose pulls the right third of the cage outwards by 5% of the width.
    const double dx = std::cos(t) > 0.5 ? 0.05 * c.width : 0.0;
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s[%.3f, %.3f]", i ? ", " : "", x, y);
    cage += buf;
    std::snprintf(buf, sizeof buf, "%s[%.3f, %.3f]", i ? ", " : "", x + dx, y);
    pose += buf;
  }
  std::ofstream(c.dir / "cage.json") << cage << "]}\n";
  std::ofstream(c.dir / "pose.json") << pose << "]}\n";
}

/// The generated cases; their folders are removed at exit unless KC_BENCH_KEEP is set.
struct Cases {
  std::map<int, Case> byTenths;
  ~Cases() {
    if (std::getenv("KC_BENCH_KEEP")) return;
    std::error_code ec;
    for (const auto& [tenths, c] : byTenths) fs::remove_all(c.dir, ec);
  }
};

Case& caseFor(int tenths) {
  static Cases all;
  std::map<int, Case>& cases = all.byTenths;
  Case& c = cases[tenths];
  if (c.dir.empty()) {
    c.dir = fs::temp_directory_path() / ("kc_bench_big_" + std::to_string(::getpid()) + "_" + std::to_string(tenths));
    fs::create_directories(c.dir);
    if (tenths <= 0) return c;  // a case of its own (figureCase)
    c.width = sizeForTenthsOfMegapixels(tenths, true);
    c.height = sizeForTenthsOfMegapixels(tenths, false);
    writePicture(c.dir / "picture.png", c.width, c.height);
    writeCageAndPose(c);
  }
  return c;
}

struct ChildRun {
  double seconds = 0, peakMB = 0;
  int status = -1;
};

/// Runs kcwarp-cli with `args` (stdout and stderr to log.txt in the case's folder): its wall time
/// and, through /usr/bin/time when installed, its peak resident memory. (The child's own rusage
/// would not do: a process spawned from this one inherits this one's high-water mark at exec; time
/// forks the CLI from its own small process.)
ChildRun runCli(const Case& c, const std::vector<std::string>& args) {
  const bool timed = fs::exists("/usr/bin/time");
  const std::string memory = (c.dir / "peak_kb.txt").string();
  std::vector<std::string> all;
  if (timed) all = {"/usr/bin/time", "-f", "%M", "-o", memory};
  all.push_back(KC_CLI_PATH);
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log = (c.dir / "log.txt").string();
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  ChildRun r;
  const auto t0 = Clock::now();
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return r;
  waitpid(pid, &r.status, 0);
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  double kb = 0;
  if (timed && (std::ifstream(memory) >> kb)) r.peakMB = kb / 1024.0;
  return r;
}

std::string path(const Case& c, const char* name) { return (c.dir / name).string(); }

/// The last line the CLI wrote (why it failed).
std::string lastLogLine(const Case& c) {
  std::ifstream in(c.dir / "log.txt");
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

void bindCase(benchmark::State& state, Case& c) {
  const ChildRun r = runCli(c, {"bind", "--cage", path(c, "cage.json"), "--image", path(c, "picture.png"), "-o",
                                path(c, "session.kcw.json")});
  if (r.status != 0) {
    state.SkipWithError(("bind failed: " + lastLogLine(c)).c_str());
    return;
  }
  c.bound = true;
  state.SetIterationTime(r.seconds);
  state.counters["peak_MB"] = r.peakMB;
  state.counters["file_MB"] = double(fs::file_size(c.dir / "session.kcw.json")) / 1e6;
}

/// The case of this row, bound (by the Bind row, or here when it was filtered out).
Case* boundCase(benchmark::State& state, Case& c) {
  state.SetLabel(std::to_string(c.width) + "x" + std::to_string(c.height));
  if (!c.bound) {
    const ChildRun r = runCli(c, {"bind", "--cage", path(c, "cage.json"), "--image", path(c, "picture.png"), "-o",
                                  path(c, "session.kcw.json")});
    c.bound = r.status == 0;
    if (!c.bound) state.SkipWithError(("bind failed: " + lastLogLine(c)).c_str());
  }
  return c.bound ? &c : nullptr;
}
Case* boundCase(benchmark::State& state) { return boundCase(state, caseFor(static_cast<int>(state.range(0)))); }

void BM_Bind(benchmark::State& state) {
  Case& c = caseFor(static_cast<int>(state.range(0)));
  state.SetLabel(std::to_string(c.width) + "x" + std::to_string(c.height));
  for (auto _ : state) bindCase(state, c);
}

void oneShotWarp(benchmark::State& state, Case* c) {
  for (auto _ : state) {
    if (!c) break;
    const ChildRun r = runCli(*c, {"warp", "--session", path(*c, "session.kcw.json"), "--image", path(*c, "picture.png"),
                                   "--pose", path(*c, "pose.json"), "-o", path(*c, "warped.png")});
    if (r.status != 0) {
      state.SkipWithError(("warp failed: " + lastLogLine(*c)).c_str());
      break;
    }
    state.SetIterationTime(r.seconds);
    state.counters["peak_MB"] = r.peakMB;
  }
}
void BM_OneShotWarp(benchmark::State& state) { oneShotWarp(state, boundCase(state)); }

void BM_SessionLoad(benchmark::State& state) {
  Case* c = boundCase(state);
  for (auto _ : state) {
    if (!c) break;
    const auto t0 = Clock::now();
    const kc::app::Session s = kc::app::loadSession(path(*c, "session.kcw.json"));
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
    state.counters["samples"] = double(s.samples.size());
    state.counters["file_MB"] = double(fs::file_size(c->dir / "session.kcw.json")) / 1e6;
  }
}

void BM_Export(benchmark::State& state) {
  Case* c = boundCase(state);
  if (!c) return;
  const kc::app::Session s = kc::app::loadSession(path(*c, "session.kcw.json"));
  const kc::Image source = kc::app::loadImage(path(*c, "picture.png"));
  const kc::Pose pose = kc::app::loadPose(path(*c, "pose.json"), s.cage.C);
  const std::string out = path(*c, "export.png");
  for (auto _ : state) {
    // saveImage's steps one by one, each timed: where the export's time goes.
    const auto t0 = Clock::now();
    kc::WarpMesh mesh = kc::app::buildWarpMesh(s, kc::app::warpMeshOptionsFor(s));
    const auto t1 = Clock::now();
    mesh.deform(pose);
    const auto t2 = Clock::now();
    const kc::Image picture = mesh.render(source, kc::RasterOptions{});
    const auto t3 = Clock::now();
    const std::string bytes = kc::app::encodeImage(picture, kc::app::imageExtension(out));
    const auto t4 = Clock::now();
    kc::app::writeFileAtomic(out, bytes);
    const auto t5 = Clock::now();
    const auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
    state.SetIterationTime(seconds(t0, t5));
    state.counters["mesh_s"] = seconds(t0, t1);
    state.counters["deform_s"] = seconds(t1, t2);
    state.counters["render_s"] = seconds(t2, t3);
    state.counters["encode_s"] = seconds(t3, t4);
    state.counters["write_s"] = seconds(t4, t5);
    state.counters["file_MB"] = double(bytes.size()) / 1e6;
  }
}

void BM_PerPose(benchmark::State& state) {
  Case* c = boundCase(state);
  if (!c) return;
  const kc::app::Session s = kc::app::loadSession(path(*c, "session.kcw.json"));
  const kc::Pose target = kc::app::loadPose(path(*c, "pose.json"), s.cage.C);
  kc::WarpMesh mesh = kc::app::buildWarpMesh(s, kc::app::warpMeshOptionsFor(s));
  constexpr int kPoses = 20;
  for (auto _ : state) {
    double seconds = 0.0, repair = 0.0;
    for (int k = 1; k <= kPoses; ++k) {
      kc::Pose pose = target;
      for (kc::HandlePose& h : pose) h.translate *= double(k) / kPoses;
      const auto t0 = Clock::now();
      const kc::DeformReport r = mesh.deform(pose, kc::DeformPass::Live);
      seconds += std::chrono::duration<double>(Clock::now() - t0).count();
      repair += r.repairSeconds;
    }
    state.SetIterationTime(seconds / kPoses);
    state.counters["repair_ms"] = 1e3 * repair / kPoses;
    state.counters["vertices"] = double(mesh.restVertices().rows());
  }
}

void BM_Floor(benchmark::State& state) {
  Case& c = caseFor(static_cast<int>(state.range(0)));
  state.SetLabel(std::to_string(c.width) + "x" + std::to_string(c.height));
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const cv::Mat img = cv::imread(path(c, "picture.png"), cv::IMREAD_UNCHANGED);
    cv::Mat mapX(img.rows, img.cols, CV_32F), mapY(img.rows, img.cols, CV_32F);
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) {  // a gentle swirl
        mapX.at<float>(y, x) = float(x + 0.02 * img.cols * std::sin(y * 6.283 / img.rows));
        mapY.at<float>(y, x) = float(y);
      }
    cv::Mat out;
    cv::remap(img, out, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    cv::imwrite(path(c, "floor.png"), out, {cv::IMWRITE_PNG_COMPRESSION, kc::app::kDefaultPngCompression});
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
  }
}

/// The bundled figure scaled to 2048×2048 (picture, cage and pose; rotations kept), its key in
/// Cases −1. Against the rigid-MLS peer of bench/mls_peer.h on the same picture and points.
Case& figureCase() {
  static Case* made = nullptr;
  if (made) return *made;
  Case& c = caseFor(-1);
  const std::string base = std::string(KC_SOURCE_DIR) + "/images/figure";
  const cv::Mat small = cv::imread(base + ".png", cv::IMREAD_UNCHANGED);
  const double sx = 2048.0 / small.cols, sy = 2048.0 / small.rows;
  cv::Mat big;
  cv::resize(small, big, cv::Size(2048, 2048), 0, 0, cv::INTER_CUBIC);
  cv::imwrite(path(c, "picture.png"), big, {cv::IMWRITE_PNG_COMPRESSION, kc::app::kDefaultPngCompression});
  const kc::Cage cage = kc::app::loadCage(base + ".cage.json");
  const kc::Pose pose = kc::app::loadPose(base + ".pose.json", cage.C);
  std::string cageJson = R"({"version": 1, "closed": true, "points": [)", poseJson = R"({"version": 1, "handles": [)";
  for (kc::Index i = 0; i < cage.size(); ++i) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s[%.4f, %.4f]", i ? ", " : "", cage.C(i, 0) * sx, cage.C(i, 1) * sy);
    cageJson += buf;
    const kc::HandlePose& h = pose[std::size_t(i)];
    std::snprintf(buf, sizeof buf, R"(%s{"translate": [%.4f, %.4f], "rotate": %.6f})", i ? ", " : "", h.translate.x() * sx,
                  h.translate.y() * sy, h.rotate);
    poseJson += buf;
  }
  std::ofstream(c.dir / "cage.json") << cageJson << "]}\n";
  std::ofstream(c.dir / "pose.json") << poseJson << "]}\n";
  c.width = c.height = 2048;
  made = &c;
  return c;
}

void BM_FigureOneShotWarp(benchmark::State& state) { oneShotWarp(state, boundCase(state, figureCase())); }

/// The peer: read, rigid MLS on a 5-px grid with the cage points as handles, remap, write (same
/// PNG level as kcwarp), in this process (no process start, unlike the row above).
void BM_FigureMlsPeer(benchmark::State& state) {
  Case& c = figureCase();
  state.SetLabel("2048x2048");
  const kc::Cage cage = kc::app::loadCage(path(c, "cage.json"));
  const kc::Points posed = kc::posedControls(cage.C, kc::app::loadPose(path(c, "pose.json"), cage.C));
  std::vector<kc::bench::Complex> from, to;
  for (kc::Index i = 0; i < cage.size(); ++i) {
    from.emplace_back(cage.C(i, 0), cage.C(i, 1));
    to.emplace_back(posed(i, 0), posed(i, 1));
  }
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const cv::Mat img = cv::imread(path(c, "picture.png"), cv::IMREAD_UNCHANGED);
    cv::imwrite(path(c, "mls.png"), kc::bench::rigidMlsWarp(img, from, to),
                {cv::IMWRITE_PNG_COMPRESSION, kc::app::kDefaultPngCompression});
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
  }
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int tenths : {1, 10, 40, 120}) b->Arg(tenths);
  b->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
}

}  // namespace

BENCHMARK(BM_Floor)->Apply(sizes);
BENCHMARK(BM_Bind)->Apply(sizes);
BENCHMARK(BM_SessionLoad)->Apply(sizes);
BENCHMARK(BM_Export)->Apply(sizes);
BENCHMARK(BM_OneShotWarp)->Apply(sizes);
BENCHMARK(BM_PerPose)->Apply(sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FigureMlsPeer)->Iterations(3)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FigureOneShotWarp)->Iterations(3)->UseManualTime()->Unit(benchmark::kMillisecond);

namespace {

/// Peak memory of a bind at a fine resolution: the bundled star scaled ×5 onto 1600×1600 and bound
/// at h = 6 px, so about 20,000 samples lie inside the cage or on it (the vertices of a 20k-vertex
/// mesh of its interior), plus the default exterior band (its bounding box). `kcwarp-cli bind` as a
/// child process; counters: peak_MB (its peak resident memory), samples (in all), inside (inside the
/// cage or on it).
void BM_BindStar20k(benchmark::State& state) {
  Case c;
  c.width = c.height = 1600;
  c.dir = fs::temp_directory_path() / ("kc_bench_star20k_" + std::to_string(::getpid()));
  fs::create_directories(c.dir);
  kc::Cage star = kc::app::loadCage(std::string(KC_SOURCE_DIR) + "/images/star.cage.json");
  star.C *= 5.0;
  kc::app::saveCage(path(c, "cage.json"), star);
  for (auto _ : state) {
    const ChildRun r = runCli(c, {"bind", "--cage", path(c, "cage.json"), "--size", "1600,1600", "--spacing", "6", "-o",
                                  path(c, "session.kcw.json")});
    if (r.status != 0) {
      state.SkipWithError(("bind failed: " + lastLogLine(c)).c_str());
      break;
    }
    state.SetIterationTime(r.seconds);
    state.counters["peak_MB"] = r.peakMB;
    const kc::app::Session s = kc::app::loadSession(path(c, "session.kcw.json"));
    state.counters["samples"] = double(s.samples.size());
    double inside = 0;
    for (const kc::SampleKind k : s.samples.kind) inside += k != kc::SampleKind::Exterior;
    state.counters["inside"] = inside;
  }
  if (!std::getenv("KC_BENCH_KEEP")) {
    std::error_code ec;
    fs::remove_all(c.dir, ec);
  }
}

}  // namespace

BENCHMARK(BM_BindStar20k)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
