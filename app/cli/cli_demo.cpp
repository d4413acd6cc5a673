// kcwarp-cli demo: binds and warps every bundled example (images/) end to end and writes the
// warped PNGs, weight heatmaps, sessions and a short text report (timings, property table).

#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.h"
#include "kc/app/diagnostics.h"
#include "kc/app/errors.h"
#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/heatmap.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"
#include "kc/core/outside_motion.h"
#include "kc/core/warp_mesh.h"

#ifndef KC_EXAMPLES_DIR
#define KC_EXAMPLES_DIR "images"
#endif

namespace kc::cli {
namespace {

namespace fs = std::filesystem;

/// printf into both stdout and the report text.
void say(std::string& report, const char* fmt, ...) {
  char buf[1024];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  std::fputs(buf, stdout);
  report += buf;
}

/// The examples folder: --images, else ./images, else the source tree's images/ (compiled in).
std::string findExamples(const std::string& given) {
  if (!given.empty()) {
    if (!fs::is_directory(given)) throw app::InputError(given, "no such folder");
    return given;
  }
  for (const std::string& dir : {std::string("images"), std::string(KC_EXAMPLES_DIR)})
    if (fs::exists(fs::path(dir) / "checker.cage.json")) return dir;
  throw app::InputError("--images", "cannot find the bundled examples (images/checker.cage.json); give --images DIR");
}

/// The control point the pose moves most: the heatmap shows its weights.
Index mostMoved(const Pose& pose) {
  Index best = 0;
  double score = -1;
  for (std::size_t i = 0; i < pose.size(); ++i) {
    const double s = pose[i].translate.norm() + 50.0 * std::abs(pose[i].rotate);
    if (s > score) score = s, best = Index(i);
  }
  return best;
}

/// The inputs of one bundled example, all read and checked before any work starts.
struct Example {
  std::string name, base;
  Cage cage;
  Pose pose;
  Image source;
};

Example loadExample(const std::string& dir, const std::string& name) {
  Example e;
  e.name = name;
  e.base = (fs::path(dir) / name).string();
  e.cage = app::loadCage(e.base + ".cage.json");
  e.pose = app::loadPose(e.base + ".pose.json", e.cage.C);
  e.source = app::loadImage(e.base + ".png");
  return e;
}

/// Binds and warps one example; its output files go into `files` (written at the end).
void runExample(const Example& e, const std::string& out, OutsideMode outside, int pngCompression,
                app::OutputBatch& files, std::string& report) {
  const auto png = [pngCompression](const Image& image) { return app::encodeImage(image, ".png", pngCompression); };
  const std::string& name = e.name;
  const std::string& base = e.base;
  const Cage& cage = e.cage;
  const Pose& pose = e.pose;
  const Image& source = e.source;

  app::BindReport br;
  app::Session s = app::bind(cage, source.width, source.height, app::BindParams{}, &br);
  const std::string sessionPath = (fs::path(out) / (name + ".kcw.json")).string();
  s.image = app::imagePathForSession(base + ".png", sessionPath);
  s.pose = pose;
  s.outside = toString(outside);
  files.set(sessionPath, app::sessionToJson(s));

  app::WarpExportReport er;
  WarpMeshOptions meshOptions;
  meshOptions.outside = outside;
  WarpMesh mesh = app::buildWarpMesh(s, meshOptions, &er);
  const CompactWeightsReport& cw = er.weights;
  const double vertexMs = 1e3 * er.weightSeconds;
  const DeformReport dr = mesh.deform(pose);
  const OutsideMotion om = measureOutside(mesh);
  RasterReport rr;
  Image warped = mesh.render(source, {}, &rr);
  files.set((fs::path(out) / (name + ".warped.png")).string(), png(warped));
  app::drawCage(warped, cage, app::OverlayStyle{}.restCage);
  app::drawDeformedCage(warped, cage, posedControls(cage.C, pose));
  files.set((fs::path(out) / (name + ".overlay.png")).string(), png(warped));

  const Index control = mostMoved(pose);
  app::HeatmapOptions ho;
  files.set((fs::path(out) / (name + ".heatmap.png")).string(), png(app::weightHeatmap(s, control, ho)));
  ho.scale = app::HeatScale::Log;
  files.set((fs::path(out) / (name + ".heatmap-log.png")).string(), png(app::weightHeatmap(s, control, ho)));
  Image samples = source;
  app::drawSamples(samples, s.samples);
  app::drawCage(samples, cage, app::OverlayStyle{}.restCage);
  files.set((fs::path(out) / (name + ".samples.png")).string(), png(samples));

  const app::Diagnostics d = app::diagnose(s);
  const app::BindTimings& t = s.timings;
  say(report, "\n== %s: %dx%d image, %ld control points, %ld samples, sigma %.3g px, method %s\n", name.c_str(),
      source.width, source.height, long(cage.size()), long(s.samples.size()), s.sigma,
      std::string(app::toString(s.params.kc.method)).c_str());
  say(report, "%s\n", s.reports.summary().c_str());
  say(report, "bind %.3f s (sampling %.3f, kernel %.3f, factor %.3f, init %.3f, optimize %.3f, solve %.3f)\n", t.total,
      t.sampling, t.assemble, t.factor, t.init, t.optimize, t.solve);
  say(report, "%-34s %12s %12s %12s\n", "property", "samples", "inside", "image");
  say(report, "%-34s %12.2e %12.2e %12.2e\n", "partition of unity max|sum w-1|", d.samples.partitionOfUnity,
      d.inside.partitionOfUnity, d.image.partitionOfUnity);
  say(report, "%-34s %12.2e %12.2e %12.2e\n", "reproduction max|sum w c - x| px", d.samples.reproduction,
      d.inside.reproduction, d.image.reproduction);
  say(report, "%-34s %12.3f %12.3f %12.3f\n", "min weight", d.samples.minWeight, d.inside.minWeight, d.image.minWeight);
  say(report, "%-34s %12.2e\n", "Lagrange max|w_i(c_j)-d_ij|", d.lagrange);
  say(report, "locality: %.2f controls influence a point on average (max %d)\n", d.locality.meanInfluencing,
      d.locality.maxInfluencing);
  say(report, "warp: mesh %ld vertices / %ld triangles, weights at vertices %.1f ms, compact %.0f KB vs dense %.0f KB "
              "(%.2f entries per vertex)\n",
      long(mesh.restVertices().rows()), long(mesh.triangles().size()), vertexMs, cw.compactBytes / 1024.0,
      cw.denseBytes / 1024.0, cw.meanPerVertex);
  say(report, "      deform %.3f ms, render %.1f ms, flipped triangles %ld (%.1f px^2), det J in [%.2f, %.2f]\n",
      dr.seconds * 1e3, rr.seconds * 1e3, long(dr.flippedTriangles), dr.flippedArea, dr.minJacobian, dr.maxJacobian);
  say(report, "      outside (%s): corners moved %.2f px, background 50 px from the cage moved mean %.2f max %.2f px, "
              "200 px mean %.2f max %.2f px, weights in [%.2f, %.2f], fold-overs outside %ld\n",
      std::string(toString(outside)).c_str(), om.cornerMax, om.bands[0].mean, om.bands[0].max, om.bands[1].mean, om.bands[1].max,
      om.minWeight, om.maxWeight, long(om.flippedOutside));
  say(report, "      heatmaps show w%ld (the control the pose moves most)\n", long(control));
}

}  // namespace

void addDemoCommand(CLI::App& app) {
  struct Args {
    std::string out = "kcwarp-demo", images, outside = "pinned";
    int pngCompression = app::kDefaultPngCompression;
  };
  auto a = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("demo", "Bind and warp the bundled examples; write PNGs, heatmaps and a report");
  sub->add_option("--out", a->out, "Output folder")->capture_default_str();
  sub->add_option("--images", a->images, "Folder with the examples (default: ./images or the source tree's)");
  sub->add_option("--outside", a->outside, kOutsideHelp)->capture_default_str();
  addPngCompressionOption(sub, a->pngCompression);
  sub->callback([a] {
    const OutsideMode outside = parseOption<OutsideMode>(a->outside, "--outside");
    const std::string dir = findExamples(a->images);
    std::error_code ec;
    if (fs::exists(a->out, ec) && !fs::is_directory(a->out, ec)) throw app::InputError(a->out, "exists and is not a folder");
    std::vector<Example> examples;
    for (const char* name : {"checker", "star", "figure"}) examples.push_back(loadExample(dir, name));
    std::string report = "kcwarp demo: bundled examples from " + dir + "\n";
    std::fputs(report.c_str(), stdout);
    // Outputs are checked as they are produced and written together once every example worked.
    const bool created = fs::create_directories(a->out, ec);
    if (!fs::is_directory(a->out, ec)) throw app::InputError(a->out, "cannot create the output folder: " + ec.message());
    const std::string path = (fs::path(a->out) / "report.txt").string();
    try {
      app::OutputBatch files;
      files.reserve(path);
      for (const Example& e : examples) runExample(e, a->out, outside, a->pngCompression, files, report);
      files.set(path, report);
      files.commit();
    } catch (...) {
      if (created) fs::remove(a->out, ec);  // only when still empty
      throw;
    }
    std::printf("\nwrote %s and the PNGs next to it\n", path.c_str());
  });
}

}  // namespace kc::cli
