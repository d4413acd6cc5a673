// kcwarp-cli stats: the property table, locality figures and timings of a session.

#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "cli_report.h"
#include "kc/app/text.h"
#include "kc/app/diagnostics.h"
#include "kc/app/file_io.h"
#include "kc/app/line_metrics.h"

namespace kc::cli {
namespace {

using nlohmann::json;

json rowJson(const app::PropertyRow& r) {
  return {{"points", r.points},
          {"partition_of_unity", r.partitionOfUnity},
          {"reproduction", r.reproduction},
          {"min_weight", r.minWeight},
          {"negatives", r.negatives}};
}

/// The session's points and parameters: KC's samples and σ, or LBC's mesh and solver options.
void printHeader(const app::Session& s, const std::string& path) {
  Index counts[5] = {0, 0, 0, 0, 0};
  for (SampleKind k : s.samples.kind) ++counts[static_cast<int>(k)];
  std::printf("session %s\n", path.c_str());
  if (s.report.meshVertices() > 0) {
    std::printf(
        "  %ld control points, %s mesh of the cage interior: %ld vertices (%ld on cage edges, %ld interior), image %dx%d\n",
        static_cast<long>(s.cage.size()), std::string(app::backendFor(s.params.backend).displayName()).c_str(),
        static_cast<long>(s.samples.size()), static_cast<long>(counts[1]), static_cast<long>(counts[3]), s.imageWidth,
        s.imageHeight);
    std::printf("  backend %s, spacing %.4g px, %s\n\n", s.params.backend.c_str(), s.params.spacing,
                app::parametersText(app::backendFor(s.params.backend), s.params).c_str());
    return;
  }
  std::printf("  %ld control points, %ld samples (%ld edge, %ld interior, %ld exterior), image %dx%d\n", static_cast<long>(s.cage.size()),
              static_cast<long>(s.samples.size()), static_cast<long>(counts[1]), static_cast<long>(counts[3]),
              static_cast<long>(counts[4]), s.imageWidth, s.imageHeight);
  const app::Backend& backend = app::backendFor(s.params.backend);
  std::printf("  backend %s, spacing %.4g px", s.params.backend.c_str(), s.params.spacing);
  if (backend.capabilities().targets) std::printf(", sigma %.4g px", s.sigma);  // kernel coordinates: the σ used
  if (const std::string own = app::parametersText(backend, s.params); !own.empty()) std::printf(", %s", own.c_str());
  std::printf("\n\n");
}

/// The property table: at the field's own points, inside the cage and — when the field has
/// weights there — over the whole image; a field without outside weights says so instead.
void printProperties(const app::Session& s, const app::Diagnostics& d) {
  const app::PropertyRow* rows[] = {&d.samples, &d.inside, &d.image};
  const int columns = d.outsideWeights ? 3 : 2;
  std::printf("%-38s %14s %14s", "property", s.report.meshVertices() > 0 ? "mesh vertices" : "samples (W)", "inside cage");
  if (d.outsideWeights) std::printf(" %14s", "whole image");
  std::printf("\n");
  auto row = [&](const char* name, auto field, const char* fmt) {
    std::printf("%-38s", name);
    for (int c = 0; c < columns; ++c) std::printf(fmt, field(*rows[c]));
    std::printf("\n");
  };
  row("partition of unity  max|sum w - 1|", [](const app::PropertyRow& r) { return r.partitionOfUnity; }, " %14.3e");
  row("reproduction        max|sum w c - x| px", [](const app::PropertyRow& r) { return r.reproduction; }, " %14.3e");
  row("min weight", [](const app::PropertyRow& r) { return r.minWeight; }, " %14.3e");
  row("negative weights    (< -1e-6)", [](const app::PropertyRow& r) { return static_cast<long>(r.negatives); }, " %14ld");
  row("points", [](const app::PropertyRow& r) { return static_cast<long>(r.points); }, " %14ld");
  if (!d.outsideWeights) {
    if (s.params.exterior == sampling::ExteriorExtent::Band && s.report.meshVertices() == 0)
      std::printf("%-38s only in a band around the cage (bound with --exterior band: warps keep or pin the\n"
                  "%-38s outside; --outside deform is refused, bind with --exterior frame for it)\n", "outside the cage", "");
    else
      std::printf("%-38s no weights: the field covers the cage interior only (warps keep or pin the outside;\n"
                  "%-38s --outside deform is refused)\n", "outside the cage", "");
  }
  std::printf("%-38s %14.3e\n", "Lagrange            max|w_i(c_j) - d_ij|", d.lagrange);
  std::printf("%-38s %14.3e\n", "linear precision on edges  max dev.", d.edgeLinearity);
  if (d.sticks) std::printf("%-38s %14.3e\n", "  on the sticks alone       max dev.", d.stickLinearity);
}

/// Structure lines: how straight and parallel they stay under random translations (every control
/// moved by up to ±40 px, 50 poses).
constexpr int kLineTrials = 50;
constexpr double kLineTranslation = 40.0;

void printLines(const app::Session& s) {
  if (s.structure.lines.empty() || !s.hasField()) return;
  const app::LineFigures f = app::measureLines(s, s.structure.lines, kLineTrials, kLineTranslation);
  std::printf("%-38s %14.3e  (%zu lines; %d random translations of every control by up to +-%g px)\n",
              "structure lines  bend px", f.deviation, s.structure.lines.size(), kLineTrials, kLineTranslation);
  bool grouped = false;
  for (const StructureLine& l : s.structure.lines) grouped = grouped || l.group >= 0;
  if (grouped) std::printf("%-38s %14.3e\n", "  parallel groups  angle deg", f.angle);
}

void printText(const app::Session& s, const app::Diagnostics& d, const std::string& path) {
  printHeader(s, path);
  printProperties(s, d);
  printLines(s);
  std::printf("\nlocality inside the cage (LBC eq. 19-21, every %d px):\n%s", d.pixelStep, localityText(d, "  ").c_str());
  std::printf("\n%s\n", s.report.summary().c_str());
  if (s.report.backend) std::printf("%s", s.report.backend->details(s.params, "  ").c_str());
  for (const std::string& p : s.report.problems()) std::printf("  warning: %s\n", p.c_str());
  const app::BindTimings& t = s.report.timings;
  if (s.report.meshVertices() > 0)
    std::printf("\ntimings (s): mesh %.3f  geodesics %.3f  factor %.3f  ADMM %.3f  bind total %.3f\n", t.sampling, t.init,
                t.factor, t.optimize, t.total);
  else
    std::printf("\ntimings (s): sampling %.3f  kernel %.3f  factor %.3f  init %.3f  optimize %.3f  solve %.3f  bind total %.3f\n",
                t.sampling, t.assemble, t.factor, t.init, t.optimize, t.solve, t.total);
  std::printf("             property evaluation %.3f\n", d.evalSeconds);
}

}  // namespace

void addStatsCommand(CLI::App& app) {
  struct Args {
    std::string session;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("stats", "Property table, locality and timings of a session");
  sub->add_option("--session", a->session, "Session file")->required();
  sub->add_flag("--json", a->json, "Machine-readable output");
  sub->callback([a] {
    const app::Session s = app::loadSession(a->session);
    const app::Diagnostics d = app::diagnose(s);
    if (!a->json) {
      printText(s, d, a->session);
      return;
    }
    const app::BindTimings& t = s.report.timings;
    json j = {{"backend", s.params.backend},
              {"controls", s.cage.size()},
              {"samples", s.samples.size()},
              {"sigma", s.sigma},
              {"spacing", s.params.spacing},
              {"method", std::string(app::toString(s.params.kc.method))},
              {"init", std::string(app::toString(s.params.kc.init.method))},
              {"interp", std::string(app::toString(s.params.kc.interp))},
              {"properties",
               {{"samples", rowJson(d.samples)},
                {"inside", rowJson(d.inside)},
                {"image", d.outsideWeights ? rowJson(d.image) : json(nullptr)},
                {"outside_weights", d.outsideWeights},
                {"lagrange", d.lagrange},
                {"edge_linearity", d.edgeLinearity},
                {"stick_linearity", d.sticks ? json(d.stickLinearity) : json(nullptr)}}},
              {"locality",
               {{"t", d.locality.t},
                {"P", d.locality.P},
                {"Q", d.locality.Q},
                {"mean_influencing", d.locality.meanInfluencing},
                {"max_influencing", d.locality.maxInfluencing},
                {"compact_fraction", d.compactFraction},
                {"drag",
                 {{"drag_px", app::kDragPixels},
                  {"visible_shift_px", app::kVisibleShift},
                  {"weight_threshold", app::kDragWeight},
                  {"step_px", d.drag.step},
                  {"points", d.drag.points},
                  {"mean_area_fraction", d.drag.mean},
                  {"max_area_fraction", d.drag.max},
                  {"max_control", d.drag.maxControl},
                  {"area_fraction", d.drag.fraction},
                  {"min_weight", d.drag.minWeight}}}}},
              {"solver",
               {{"samples_optimized", s.report.optimize.solved},
                {"outside_control_hull", s.report.optimize.infeasible},
                {"not_optimal", s.report.optimize.failed},
                {"max_iterations", s.report.optimize.maxIterations},
                {"unreachable_targets", s.report.init.fallbackSamples},
                {"unscreened_targets", s.report.init.unscreenedSamples},
                {"sampling_converged", s.report.sampling.converged},
                {"problems", s.report.problems()}}},
              {"timings",
               {{"sampling", t.sampling},
                {"assemble", t.assemble},
                {"factor", t.factor},
                {"init", t.init},
                {"optimize", t.optimize},
                {"solve", t.solve},
                {"total", t.total},
                {"evaluate", d.evalSeconds}}}};
    if (!s.structure.lines.empty() && s.hasField()) {
      const app::LineFigures f = app::measureLines(s, s.structure.lines, kLineTrials, kLineTranslation);
      j["lines"] = {{"count", s.structure.lines.size()}, {"bend_px", f.deviation}, {"parallel_angle_deg", f.angle},
                    {"trials", kLineTrials}, {"max_translation_px", kLineTranslation}};
    }
    const app::Backend& backend = app::backendFor(s.params.backend);
    if (const std::string block(backend.parameterBlock()); !block.empty()) {  // the backend's own parameters and report
      j[block] = app::parametersToJson(backend, s.params);
      if (s.report.backend) s.report.backend->toJson(j["solver"][block], false);
    }
    if (!backend.capabilities().targets)  // the kernel coordinates' parameters mean nothing here
      for (const char* kcOnly : {"sigma", "init", "method", "interp"}) j.erase(kcOnly);
    std::cout << j.dump(2) << "\n";
  });
}

}  // namespace kc::cli
