// kcwarp-cli warp: a bound session + image + pose → warped PNG (thesis 3.37, 6.3.3), plus the
// weight heatmap of one control point (thesis Figs 6.1–6.2) and cage overlays.

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/heatmap.h"
#include "kc/app/image_io.h"
#include "kc/app/limits.h"
#include "kc/core/outside_motion.h"
#include "kc/core/warp_mesh.h"

namespace kc::cli {
namespace {

struct WarpArgs {
  std::string session, image, pose, output;
  int heatmap = -1;
  std::string heatmapOut, scale = "linear";
  bool overlay = false;
  std::string outside;  // empty: the session's choice, else pinned
  bool supersample = false;
  std::optional<double> meshSpacing;  // none: automatic (app::warpMeshOptionsFor)
  std::string background;
  int pngCompression = app::kDefaultPngCompression;
};

Rgba parseColor(const std::string& text) {
  int v[4] = {0, 0, 0, 255};
  char tail = 0;
  const int n = std::sscanf(text.c_str(), "%d,%d,%d,%d%c", &v[0], &v[1], &v[2], &v[3], &tail);
  if (n < 3 || n > 4) throw app::InputError("--background", "expected R,G,B or R,G,B,A (0..255), got '" + text + "'");
  for (int c : v)
    if (c < 0 || c > 255) throw app::InputError("--background", "channel values must be in 0..255, got '" + text + "'");
  return {std::uint8_t(v[0]), std::uint8_t(v[1]), std::uint8_t(v[2]), std::uint8_t(v[3])};
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void runWarp(const WarpArgs& a) {
  WarpMeshOptions meshOptions;
  if (!a.outside.empty()) meshOptions.outside = parseOption<OutsideMode>(a.outside, "--outside");
  if (a.meshSpacing && !(*a.meshSpacing >= 0.5 && *a.meshSpacing <= 256))
    throw app::InputError("--mesh-spacing", "must be between 0.5 and 256 pixels");
  app::HeatmapOptions heatOptions;
  heatOptions.scale = parseOption<app::HeatScale>(a.scale, "--scale");
  RasterOptions raster;
  raster.supersample = a.supersample ? 2 : 1;
  if (!a.background.empty()) raster.background = parseColor(a.background);

  // Everything is read and checked before anything is computed or written.
  const auto tLoad = std::chrono::steady_clock::now();
  const app::Session s = app::loadSession(a.session);
  const double loadMs = msSince(tLoad);
  if (a.outside.empty() && s.outside) meshOptions.outside = *s.outside;
  meshOptions.spacing = a.meshSpacing ? *a.meshSpacing : app::warpMeshOptionsFor(s).spacing;
  const Index m = s.cage.size();
  if (a.heatmap >= m) throw app::InputError("--heatmap", "control point " + std::to_string(a.heatmap) +
                                                             " does not exist (the cage has " + std::to_string(m) + ")");
  const double vertices = (s.imageWidth / meshOptions.spacing + 2.0) * (s.imageHeight / meshOptions.spacing + 2.0);
  if (!a.output.empty() && vertices > double(app::kMaxMeshVertices))
    throw app::InputError("--mesh-spacing", "a warp mesh of spacing " + std::to_string(meshOptions.spacing).substr(0, 5) + " px over " +
                                                std::to_string(s.imageWidth) + "x" + std::to_string(s.imageHeight) +
                                                " would have about " + std::to_string(static_cast<long long>(vertices)) +
                                                " vertices, above kcwarp's limit of " + std::to_string(app::kMaxMeshVertices) +
                                                "; use a larger --mesh-spacing");
  app::OutputBatch outputs;
  if (a.heatmap >= 0) {
    app::imageExtension(a.heatmapOut);
    outputs.reserve(a.heatmapOut);
  }
  Image source;
  double readMs = 0.0;
  Pose pose;
  std::string imagePath;
  if (!a.output.empty()) {
    app::imageExtension(a.output);
    outputs.reserve(a.output);
    imagePath = a.image.empty() ? app::resolveSessionImage(s.image, a.session) : a.image;
    if (imagePath.empty()) throw app::InputError("--image", "the session names no image; give --image I.png");
    pose = a.pose.empty() ? s.pose : app::loadPose(a.pose, s.cage.C);
    try {
      validatePose(pose, m);
    } catch (const std::invalid_argument& e) {
      throw app::InputError(a.pose.empty() ? a.session : a.pose, e.what());
    }
    const auto tRead = std::chrono::steady_clock::now();
    source = app::loadImage(imagePath, s.imageUpright ? app::ImageOrientation::Upright : app::ImageOrientation::AsStored);
    readMs = msSince(tRead);
    if (source.width != s.imageWidth || source.height != s.imageHeight)
      throw app::InputError(imagePath, "image is " + std::to_string(source.width) + "x" + std::to_string(source.height) +
                                           " but the session was bound for " + std::to_string(s.imageWidth) + "x" +
                                           std::to_string(s.imageHeight));
  }

  if (a.heatmap >= 0) {
    const auto t0 = std::chrono::steady_clock::now();
    app::HeatmapReport hr;
    const Image heat = app::weightHeatmap(s, a.heatmap, heatOptions, &hr);
    outputs.set(a.heatmapOut, app::encodeImage(heat, app::imageExtension(a.heatmapOut), a.pngCompression));
    std::printf("heatmap of w%d: range [%.3g, %.3g], %s scale, %.1f ms, %s\n", a.heatmap, hr.minValue, hr.maxValue,
                a.scale.c_str(), msSince(t0), a.heatmapOut.c_str());
  }
  if (a.output.empty()) {
    outputs.commit();
    return;
  }

  const auto tMesh = std::chrono::steady_clock::now();
  app::WarpExportReport er;
  WarpMesh mesh = app::buildWarpMesh(s, meshOptions, &er);
  const double meshMs = msSince(tMesh);
  const CompactWeightsReport& cw = er.weights;
  const double bindMs = 1e3 * er.weightSeconds;
  const DeformReport dr = mesh.deform(pose);
  const OutsideMotion om = measureOutside(mesh);
  RasterReport rr;
  Image out = mesh.render(source, raster, &rr);
  if (a.overlay) {
    app::drawCage(out, s.cage, app::OverlayStyle{}.restCage);
    app::drawDeformedCage(out, s.cage, posedControls(s.cage.C, pose));
    app::drawDeformedLines(out, s, pose);
  }
  const auto tWrite = std::chrono::steady_clock::now();
  outputs.set(a.output, app::encodeImage(out, app::imageExtension(a.output), a.pngCompression));
  outputs.commit();
  const double writeMs = msSince(tWrite);

  std::printf("mesh: %ld vertices, %ld triangles (spacing %.3g px, outside %s); weights at vertices %.1f ms\n",
              long(mesh.restVertices().rows()), long(mesh.triangles().size()), meshOptions.spacing,
              nameOf(meshOptions.outside).c_str(), bindMs);
  std::printf("compact weights: %ld entries (%.2f per vertex, max %ld), %.1f KB vs dense %.1f KB\n", long(cw.nonZeros),
              cw.meanPerVertex, long(cw.maxPerVertex), cw.compactBytes / 1024.0, cw.denseBytes / 1024.0);
  std::printf("deform: %.3f ms; det J in [%.3g, %.3g]; flipped triangles: %ld (rest area %.1f px^2)\n",
              dr.seconds * 1e3, dr.minJacobian, dr.maxJacobian, long(dr.flippedTriangles), dr.flippedArea);
  if (const ExteriorWeights* ext = mesh.exteriorWeights()) {
    const ExteriorWeightsReport& e = ext->report;
    std::printf("pinned exterior: %ld vertices solved (%ld cut edges), weights in [%.3g, %.3g]; assemble %.1f ms, "
                "factor %.1f ms, %ld right-hand sides %.1f ms%s\n",
                long(e.unknowns), long(e.cutEdges), e.minWeight, e.maxWeight, 1e3 * e.assembleSeconds,
                1e3 * e.factorSeconds, long(m), 1e3 * e.solveSeconds, e.ok ? "" : " (factorization FAILED: outside kept fixed)");
    if (dr.harmonicFolds > 0)
      std::printf("fold repair: the harmonic extension folded %ld triangles outside the cage, %ld left after the repair "
                  "(%ld vertices moved, %ld of them on the image border, %.2f ms)\n",
                  long(dr.harmonicFolds), long(dr.repairedFolds), long(dr.repairVertices), long(dr.repairBorderVertices),
                  1e3 * dr.repairSeconds);
  }
  std::printf("outside the cage: corners moved %.2f px; border moved max %.2f px (%ld vertices); background 50 px from the cage moved mean %.2f max %.2f px "
              "(%ld vertices), 200 px mean %.2f max %.2f px (%ld); weights in [%.3g, %.3g]; fold-overs outside %ld",
              om.cornerMax, om.borderMax, long(om.borderMoved), om.bands[0].mean, om.bands[0].max, long(om.bands[0].vertices), om.bands[1].mean,
              om.bands[1].max, long(om.bands[1].vertices), om.minWeight, om.maxWeight, long(om.flippedOutside));
  if (mesh.exteriorWeights() && om.flippedOutside > 0)
    std::printf(" (%ld on the cage, %ld under the deformed inside)", long(om.flippedOnCage), long(om.flippedCovered));
  std::printf("\n");
  std::printf("render: %dx%d%s in %.1f ms; wrote %s\n", out.width, out.height, a.supersample ? " (2x2 supersampled)" : "",
              rr.seconds * 1e3, a.output.c_str());
  std::printf("time: session load %.0f ms, image read %.0f ms, warp mesh (exterior solve and weights) %.0f ms, deform %.0f ms, "
              "render %.0f ms, encode and write %.0f ms\n",
              loadMs, readMs, meshMs, dr.seconds * 1e3, rr.seconds * 1e3, writeMs);
}

}  // namespace

void addWarpCommand(CLI::App& app) {
  auto a = std::make_shared<WarpArgs>();
  CLI::App* sub = app.add_subcommand("warp", "Warp an image with a bound session and a pose; heatmaps of weights");
  sub->add_option("--session", a->session, "Session file (*.kcw.json)")->required();
  sub->add_option("--image", a->image, "Image to warp (default: the session's image)");
  sub->add_option("--pose", a->pose, "Pose file (default: the session's pose, or the rest pose)");
  sub->add_option("-o,--output", a->output, "Warped PNG to write (the input image's size, RGBA)");
  sub->add_option("--heatmap", a->heatmap, "Control point whose weights to draw")->check(CLI::NonNegativeNumber);
  sub->add_option("--out,--heatmap-out", a->heatmapOut, "Heatmap PNG to write (with --heatmap)");
  sub->add_option("--scale", a->scale, "Heatmap colour scale: linear | log")->capture_default_str();
  sub->add_flag("--overlay", a->overlay, "Draw the rest cage (white), the deformed cage (orange) and the deformed structure lines (magenta) on the output");
  sub->add_option("--outside", a->outside, std::string(kOutsideHelp) + ". Default: the session's choice, else pinned");
  sub->add_flag("--supersample", a->supersample, "2x2 supersampling");
  sub->add_option("--mesh-spacing", a->meshSpacing,
                  "Warp mesh spacing in pixels (default automatic: max(4, 2h/3, sqrt(W*H/65536)), h the session's sample spacing, with --init lbc its LBC mesh's)");
  sub->add_option("--background", a->background, "Colour of uncovered pixels R,G,B[,A] (default transparent)");
  addPngCompressionOption(sub, a->pngCompression);
  sub->callback([a] {
    if (a->output.empty() && a->heatmap < 0) throw app::InputError("warp", "give -o OUT.png and/or --heatmap I --out W.png");
    if (a->heatmap >= 0 && a->heatmapOut.empty()) throw app::InputError("--heatmap", "needs --out W.png");
    if (a->heatmap < 0 && !a->heatmapOut.empty()) throw app::InputError("--out", "needs --heatmap I");
    runWarp(*a);
  });
}

}  // namespace kc::cli
