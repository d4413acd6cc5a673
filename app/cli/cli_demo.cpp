// kcwarp-cli demo: binds and warps every bundled example (images/) end to end and writes the
// warped PNGs, weight heatmaps, sessions and a short text report (timings, property table).

#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cli_common.h"
#include "cli_report.h"
#include "kc/app/diagnostics.h"
#include "kc/app/errors.h"
#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/heatmap.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"
#include "kc/app/structure.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/lbc_solver.h"
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
  app::Structure structure;  ///< NAME.structure.json when the example has one (lines kept straight).
};

Example loadExample(const std::string& dir, const std::string& name) {
  Example e;
  e.name = name;
  e.base = (fs::path(dir) / name).string();
  e.cage = app::loadCage(e.base + ".cage.json");
  e.pose = app::loadPose(e.base + ".pose.json", e.cage.C);
  e.source = app::loadImage(e.base + ".png");
  if (fs::exists(e.base + ".structure.json")) e.structure = app::loadStructure(e.base + ".structure.json");
  return e;
}

/// Largest distance (px) of a line's points, moved by the session's field with `pose`, from the
/// chord of the moved ends: 0 for a line that stays straight.
double lineBend(const app::Session& s, const StructureLine& l, const Pose& pose) {
  constexpr Index kPoints = 201;
  Points P(kPoints, 2);
  for (Index k = 0; k < kPoints; ++k) P.row(k) = (l.a + (l.b - l.a) * (double(k) / double(kPoints - 1))).transpose();
  const Points Q = deformPoints(s.field->weightsAt(P), P, s.cage.C, pose);
  const Vec2 a = Q.row(0).transpose(), b = Q.row(kPoints - 1).transpose();
  double worst = 0.0;
  for (Index k = 0; k < kPoints; ++k) worst = std::max(worst, pointSegmentDistance(Q.row(k).transpose(), a, b));
  return worst;
}

/// `left` and `right` side by side (same height) with a 4 px gap of `gap` colour.
Image sideBySide(const Image& left, const Image& right, Rgba gap = {255, 255, 255, 255}) {
  Image out(left.width + 4 + right.width, std::max(left.height, right.height), gap);
  for (int y = 0; y < out.height; ++y) {
    if (y < left.height) std::copy_n(const_cast<Image&>(left).pixel(0, y), 4 * left.width, out.pixel(0, y));
    if (y < right.height) std::copy_n(const_cast<Image&>(right).pixel(0, y), 4 * right.width, out.pixel(left.width + 4, y));
  }
  return out;
}

/// The example bound again with its structure lines: NAME.structure.png shows the warp without
/// (left) and with (right) the lines, the lines drawn where the warp puts them, for the example's
/// pose without its rotations (lines are kept straight under translations; rotations may bend
/// them, thesis 5.3); the report gives each line's bend under both poses. `plain`: the example's
/// session without structure.
void runStructure(const Example& e, const app::Session& plain, const std::string& out, OutsideMode outside,
                  const std::function<std::string(const Image&)>& png, app::OutputBatch& files, std::string& report) {
  app::BindParams params;
  params.exterior = app::exteriorFor(outside);
  app::Session s = app::bind(e.cage, e.structure, e.source.width, e.source.height, params);
  Pose moved = e.pose;
  for (HandlePose& h : moved) h.rotate = 0.0;
  Image halves[2];
  const app::Session* sessions[2] = {&plain, &s};
  for (int k = 0; k < 2; ++k) {
    WarpMesh mesh = app::buildWarpMesh(*sessions[k], app::warpMeshOptionsFor(*sessions[k], outside));
    mesh.deform(moved);
    halves[k] = mesh.render(e.source);
    app::drawDeformedLines(halves[k], *sessions[k], e.structure.lines, moved);
  }
  files.set((fs::path(out) / (e.name + ".structure.png")).string(), png(sideBySide(halves[0], halves[1])));
  say(report, "structure: %zu lines (%s.structure.json), bind %.3f s with them against %.3f s without (%.2fx)\n",
      e.structure.lines.size(), e.name.c_str(), s.report.timings.total, plain.report.timings.total,
      s.report.timings.total / plain.report.timings.total);
  for (std::size_t k = 0; k < e.structure.lines.size(); ++k) {
    const StructureLine& l = e.structure.lines[k];
    say(report, "      line %zu (%.0f px): bend without / with the lines %.3f / %.4f px (pose without rotations), "
                "%.3f / %.3f px (the pose, which turns points)\n",
        k, l.length(), lineBend(plain, l, moved), lineBend(s, l, moved), lineBend(plain, l, e.pose), lineBend(s, l, e.pose));
  }
}

/// The LBC objective (LBC paper eq. 14, normalized units) of two sessions' weights on one LBC mesh
/// of their cage at `lbcParams`' spacing, with its τ: the weights at the mesh vertices, linear on
/// its triangles (the mesh and the solver's geometry built once for both).
std::pair<double, double> lbcObjectives(const app::Session& a, const app::Session& b, const app::BindParams& lbcParams) {
  CageMeshOptions mo;
  mo.spacing = lbcParams.spacing;
  const CageMesh mesh = meshCageInterior(a.cage, mo);
  const LbcSolver solver(mesh, lbcParams.lbc.tau);
  return {solver.objective(a.field->weightsAt(mesh.V)), solver.objective(b.field->weightsAt(mesh.V))};
}

/// Binds the example again with the LBC backend (defaults) and reports its solver and locality
/// next to KC's (`kc`, `kcDiag`: the example's KC session and its diagnostics); puts the LBC
/// heatmap of `control` into `files` (folder `out`).
void runLbc(const Example& e, const app::Session& kc, const app::Diagnostics& kcDiag, Index control, const std::string& out,
            const std::function<std::string(const Image&)>& png, app::OutputBatch& files, std::string& report) {
  app::BindParams params;
  params.backend = "lbc";
  params.spacing = kc.params.spacing;
  const app::Session s = app::bind(e.cage, e.source.width, e.source.height, params);
  const app::Diagnostics d = app::diagnose(s);
  app::HeatmapOptions ho;
  ho.scale = app::HeatScale::Log;
  files.set((fs::path(out) / (e.name + ".lbc.heatmap-log.png")).string(), png(app::weightHeatmap(s, control, ho)));
  const auto [kcObjective, lbcObjective] = lbcObjectives(kc, s, params);
  say(report, "-- LBC (local barycentric coordinates) on the same cage, spacing %.3g px, tau %s: bind %.3f s\n", params.spacing,
      std::string(app::toString(params.lbc.tau)).c_str(), s.report.timings.total);
  say(report, "%s\n%s", s.report.summary().c_str(), s.report.backend ? s.report.backend->details(s.params, "   ").c_str() : "");
  say(report, "%-44s %12s %12s\n", "locality inside the cage (LBC eq. 19-21)", "KC", "LBC");
  const auto P = [](const LocalityStats& l, double t) -> double {  // P(t) as tabulated by diagnose()
    for (std::size_t k = 0; k < l.t.size(); ++k)
      if (l.t[k] == t) return l.P[k];
    return NAN;
  };
  say(report, "%-44s %12.3f %12.3f\n", "  P(1e-3), mean fraction where |w_i| <= 1e-3", P(kcDiag.locality, 1e-3), P(d.locality, 1e-3));
  say(report, "%-44s %12.2f %12.2f\n", "  controls above 1e-3/m per point, mean", kcDiag.locality.meanInfluencing,
      d.locality.meanInfluencing);
  say(report, "%-44s %12d %12d\n", "  controls above 1e-3/m per point, max", kcDiag.locality.maxInfluencing, d.locality.maxInfluencing);
  for (std::size_t k = 2; k < d.locality.Q.size() && k <= 8; k += 2)
    say(report, "  Q(%zu), fraction with >= %zu controls above%*s %12.3f %12.3f\n", k, k, 4, "", kcDiag.locality.Q[k], d.locality.Q[k]);
  say(report, "%-44s %11.1f%% %11.1f%%\n", "  compact weights / dense (LBC Table 1)", 100.0 * kcDiag.compactFraction,
      100.0 * d.compactFraction);
  say(report, "%-44s %12.4g %12.4g\n", "  objective (LBC eq. 14) on the LBC mesh", kcObjective, lbcObjective);
  say(report, "      heatmap %s.lbc.heatmap-log.png shows LBC's w%ld (log scale)\n", e.name.c_str(), long(control));
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

  app::BindParams params;
  params.exterior = app::exteriorFor(outside);
  app::Session s = app::bind(cage, source.width, source.height, params);
  const std::string sessionPath = (fs::path(out) / (name + ".kcw.json")).string();
  s.image = app::imagePathForSession(base + ".png", sessionPath);
  s.pose = pose;
  s.outside = outside;
  files.set(sessionPath, app::sessionToJson(s));

  app::WarpExportReport er;
  const WarpMeshOptions meshOptions = app::warpMeshOptionsFor(s, outside);
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
  const app::BindTimings& t = s.report.timings;
  say(report, "\n== %s: %dx%d image, %ld control points, %ld samples, sigma %.3g px, method %s\n", name.c_str(),
      source.width, source.height, long(cage.size()), long(s.samples.size()), s.sigma,
      std::string(app::toString(s.params.kc.method)).c_str());
  say(report, "%s\n", s.report.summary().c_str());
  say(report, "bind %.3f s (sampling %.3f, kernel %.3f, factor %.3f, init %.3f, optimize %.3f, solve %.3f)\n", t.total,
      t.sampling, t.assemble, t.factor, t.init, t.optimize, t.solve);
  say(report, "%-34s %12s %12s %12s\n", "property", "samples", "inside", "image");
  say(report, "%-34s %12.2e %12.2e %12.2e\n", "partition of unity max|sum w-1|", d.samples.partitionOfUnity,
      d.inside.partitionOfUnity, d.image.partitionOfUnity);
  say(report, "%-34s %12.2e %12.2e %12.2e\n", "reproduction max|sum w c - x| px", d.samples.reproduction,
      d.inside.reproduction, d.image.reproduction);
  say(report, "%-34s %12.3f %12.3f %12.3f\n", "min weight", d.samples.minWeight, d.inside.minWeight, d.image.minWeight);
  say(report, "%-34s %12.2e\n", "Lagrange max|w_i(c_j)-d_ij|", d.lagrange);
  say(report, "%-34s %12.2e\n", "linearity along edges and sticks", d.edgeLinearity);
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
      nameOf(outside).c_str(), om.cornerMax, om.bands[0].mean, om.bands[0].max, om.bands[1].mean, om.bands[1].max,
      om.minWeight, om.maxWeight, long(om.flippedOutside));
  say(report, "      heatmaps show w%ld (the control the pose moves most)\n", long(control));
  if (!e.structure.empty()) runStructure(e, s, out, outside, png, files, report);
  if (cage.closed)
    runLbc(e, s, d, control, out, png, files, report);
  else  // LBC meshes a closed cage's interior: sticks have none
    say(report, "LBC is not run on this example: its open sticks have no interior to mesh (the LBC backend needs a closed cage)\n");
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
    for (const char* name : {"checker", "star", "figure", "stick"}) examples.push_back(loadExample(dir, name));
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
