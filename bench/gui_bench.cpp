// The GUI as a person uses it on a big picture: kcwarp in a real 1400×900 window under its own
// Xvfb (Mesa llvmpipe, software OpenGL), driven with real X input events (xdotool), on a
// generated photo-like picture of 0.1, 1, 4 or 12 megapixels (4:3) with the big-picture benchmark's
// 34-point cage over a quarter of it (tests/support/quarter_cage.h). One row per size; counters:
//   open_bind_s      process start → the bound picture on screen (`kcwarp PICTURE --cage CAGE`)
//   open_ms          reading the picture; texture_ms: the display texture (resampling + upload)
//   bind_s           the bind job's own time
//   display_w/h      the display texture's size
//   drag_*           frames that deformed while a control point was dragged (40 mouse moves):
//                    median frame time, per-pose deformation (median and 90th percentile),
//                    uploads and the vertex data sent per frame
//   release_*        three brush strokes (B tool, default brush, active point): median time from
//                    the stroke's release to the end of the frame showing the new weights, and of
//                    it the job (re-optimization, mesh weights, the mesh taking them) and the frame
//                    (of which the deformation with the full fold repair)
// Each row runs once (Iterations(1)). The folder (picture, state, frame log, screenshots:
// shot-001.png after the bind) is kept when KC_BENCH_KEEP is set. Needs Xvfb and xdotool.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "cli_run.h"
#include "gui_driver.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "quarter_cage.h"

namespace {

using namespace kc::test;
using Clock = std::chrono::steady_clock;

/// A photo-like picture: overlapping soft colour waves, fine texture and per-pixel noise (hashed,
/// so any size is the same picture), which compresses and decodes like a photograph.
kc::Image photoLike(int w, int h) {
  kc::Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double u = 4.0 * x / w, v = 3.0 * y / h;
      std::uint32_t n = static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u;
      n = (n ^ (n >> 13)) * 1274126177u;
      const double grain = double(n & 15u) - 7.5;
      std::uint8_t* p = img.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(std::clamp(120 + 70 * std::sin(2.1 * u + 1.3 * v) + 20 * std::sin(37 * u) + grain, 0.0, 255.0));
      p[1] = static_cast<std::uint8_t>(std::clamp(110 + 60 * std::cos(1.7 * v - 0.8 * u) + 15 * std::sin(29 * v) + grain, 0.0, 255.0));
      p[2] = static_cast<std::uint8_t>(std::clamp(100 + 80 * std::sin(3.3 * u * v) + grain, 0.0, 255.0));
      p[3] = 255;
    }
  return img;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double percentile90(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(0.9 * v.size()))];
}

/// The frame log's rows that deformed during a drag: frame, deform, upload times and bytes.
struct DragFrames {
  std::vector<double> frameMs, deformMs, uploadMs, uploadKb;
};

DragFrames readDragFrames(const fs::path& csv) {
  DragFrames d;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header: frame,time_s,frame_ms,deform_ms,upload_ms,dragging,deformed,vertices,upload_bytes
  while (std::getline(in, line)) {
    std::vector<double> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(std::atof(cell.c_str()));
    if (f.size() < 9 || f[5] != 1.0 || f[6] != 1.0) continue;
    d.frameMs.push_back(f[2]);
    d.deformMs.push_back(f[3]);
    d.uploadMs.push_back(f[4]);
    d.uploadKb.push_back(f[8] / 1024.0);
  }
  return d;
}

void BM_Gui(benchmark::State& bench) {
  const int tenths = static_cast<int>(bench.range(0));
  const int w = static_cast<int>(std::lround(std::sqrt(tenths * 1e5 * 4.0 / 3.0))), h = static_cast<int>(std::lround(tenths * 1e5 / w));
  bench.SetLabel(std::to_string(w) + "x" + std::to_string(h));
  GuiDriver gui;
  gui.dir = scratchDir("gui_bench_" + std::to_string(tenths));
  setenv("XDG_CONFIG_HOME", (gui.dir / "config").c_str(), 1);
  setenv("XDG_CACHE_HOME", (gui.dir / "cache").c_str(), 1);
  kc::app::saveImage((gui.dir / "picture.png").string(), photoLike(w, h));
  kc::app::saveCage((gui.dir / "cage.json").string(), quarterCage(w, h));
  auto fail = [&](const std::string& why) {
    bench.SkipWithError(why.c_str());
    gui.shutDown();
  };
  for (auto _ : bench) {
    if (!gui.startXvfb()) return fail("Xvfb did not start");
    const auto t0 = Clock::now();
    gui.launch(KC_GUI_PATH, {(gui.dir / "picture.png").string(), "--cage", (gui.dir / "cage.json").string()});
    bool ok = false;
    json s = gui.waitUntil([](const json& j) { return j.value("bound", false) && !j.value("busy", true); }, 900, ok);
    if (!ok) return fail("no bound picture: " + slurp(gui.dir / "app.log"));
    bench.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
    bench.counters["open_bind_s"] = std::chrono::duration<double>(Clock::now() - t0).count();
    bench.counters["open_ms"] = s["timings"]["open_ms"].get<double>();
    bench.counters["texture_ms"] = s["timings"]["texture_ms"].get<double>();
    bench.counters["bind_s"] = s["timings"]["bind_s"].get<double>();
    bench.counters["display_w"] = s["display_texture"][0].get<double>();
    bench.counters["display_h"] = s["display_texture"][1].get<double>();
    gui.key("F12");  // shot-001.png: the bound picture

    // Drag the rightmost control point to the right by a tenth of the cage's width on screen.
    const int wx = s["window"][0], wy = s["window"][1];
    std::size_t k = 0;
    for (std::size_t i = 1; i < s["controls"].size(); ++i)
      if (s["controls"][i][0].get<double>() > s["controls"][k][0].get<double>()) k = i;
    const double cx = s["controls"][k][0].get<double>() + wx, cy = s["controls"][k][1].get<double>() + wy;
    const double zoom = s["view"]["zoom"];
    gui.drag(cx, cy, cx + 0.05 * w * zoom, cy + 0.02 * h * zoom, 1, 40, 30);
    s = gui.waitUntil([](const json& j) { return j.value("undo", 0) == 1 && j.value("idle", false); }, 60, ok);
    if (!ok) return fail("the drag did not end");

    // Three brush strokes from the dragged point towards the cage's centre.
    gui.key("b");
    s = gui.waitUntil([](const json& j) { return j.value("tool", "") == "brush"; }, 10, ok);
    std::vector<double> release, job, frame, deform, reoptimize, meshWeights, setWeights, samples;
    for (int stroke = 0; stroke < 3; ++stroke) {
      const int undo = s["undo"];
      const double px = s["controls"][k][0].get<double>() + wx, py = s["controls"][k][1].get<double>() + wy;
      const double ox = s["view"]["origin"][0].get<double>() + wx + 0.5 * w * zoom, oy = s["view"]["origin"][1].get<double>() + wy + 0.5 * h * zoom;
      const double a = 0.15 + 0.1 * stroke, b = a + 0.25;
      gui.drag(px + a * (ox - px), py + a * (oy - py) + 4 * stroke, px + b * (ox - px), py + b * (oy - py) + 4 * stroke, 1, 12, 30);
      s = gui.waitUntil([undo](const json& j) { return j.value("undo", 0) == undo + 1 && !j.value("busy", true); }, 120, ok);
      if (!ok) return fail("the stroke did not re-optimize");
      const json& t = s["timings"];
      release.push_back(t["release_to_picture_ms"]);
      job.push_back(t["release_job_ms"]);
      frame.push_back(t["release_frame_ms"]);
      deform.push_back(t["deform_ms"]);  // the release frame's deformation (the full fold repair)
      reoptimize.push_back(t["reoptimize_ms"]);
      meshWeights.push_back(t["mesh_weights_ms"]);
      setWeights.push_back(t["mesh_set_weights_ms"]);
      samples.push_back(t["reoptimize_samples"]);
    }
    gui.key("F12");  // shot-002.png: after the strokes (heatmap)
    gui.pause(500);
    gui.shutDown();  // the frame log is written at exit

    const DragFrames d = readDragFrames(gui.dir / "frames.csv");
    bench.counters["drag_frames"] = double(d.frameMs.size());
    bench.counters["drag_frame_ms"] = median(d.frameMs);
    bench.counters["drag_deform_ms"] = median(d.deformMs);
    bench.counters["drag_deform_p90_ms"] = percentile90(d.deformMs);
    bench.counters["drag_upload_ms"] = median(d.uploadMs);
    bench.counters["drag_upload_kb"] = median(d.uploadKb);
    bench.counters["release_ms"] = median(release);
    bench.counters["release_job_ms"] = median(job);
    bench.counters["release_frame_ms"] = median(frame);
    bench.counters["release_deform_ms"] = median(deform);
    bench.counters["reoptimize_ms"] = median(reoptimize);
    bench.counters["mesh_weights_ms"] = median(meshWeights);
    bench.counters["set_weights_ms"] = median(setWeights);
    bench.counters["stroke_samples"] = median(samples);
  }
  if (!std::getenv("KC_BENCH_KEEP")) {
    std::error_code ec;
    fs::remove_all(gui.dir, ec);
  }
}

}  // namespace

BENCHMARK(BM_Gui)->Arg(1)->Arg(10)->Arg(40)->Arg(120)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
