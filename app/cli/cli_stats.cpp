// kcwarp-cli stats: the property table, locality figures and timings of a session.

#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "kc/app/diagnostics.h"
#include "kc/app/file_io.h"

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

void printText(const app::Session& s, const app::Diagnostics& d, const std::string& path) {
  const Index m = s.cage.size();
  Index counts[5] = {0, 0, 0, 0, 0};
  for (SampleKind k : s.samples.kind) ++counts[static_cast<int>(k)];
  std::printf("session %s\n", path.c_str());
  std::printf("  %ld control points, %ld samples (%ld edge, %ld interior, %ld exterior), image %dx%d\n", static_cast<long>(m),
              static_cast<long>(s.samples.size()), static_cast<long>(counts[1]), static_cast<long>(counts[3]),
              static_cast<long>(counts[4]), s.imageWidth, s.imageHeight);
  std::printf("  spacing %.4g px, sigma %.4g px, init %s, method %s, interp %s\n\n", s.params.spacing, s.sigma,
              std::string(app::toString(s.params.kc.init.method)).c_str(), std::string(app::toString(s.params.kc.method)).c_str(),
              std::string(app::toString(s.params.kc.interp)).c_str());
  std::printf("%-38s %14s %14s %14s\n", "property", "samples (W)", "inside cage", "whole image");
  auto row = [](const char* name, double a, double b, double c) { std::printf("%-38s %14.3e %14.3e %14.3e\n", name, a, b, c); };
  row("partition of unity  max|sum w - 1|", d.samples.partitionOfUnity, d.inside.partitionOfUnity, d.image.partitionOfUnity);
  row("reproduction        max|sum w c - x| px", d.samples.reproduction, d.inside.reproduction, d.image.reproduction);
  row("min weight", d.samples.minWeight, d.inside.minWeight, d.image.minWeight);
  std::printf("%-38s %14ld %14ld %14ld\n", "negative weights    (< -1e-6)", static_cast<long>(d.samples.negatives),
              static_cast<long>(d.inside.negatives), static_cast<long>(d.image.negatives));
  std::printf("%-38s %14ld %14ld %14ld\n", "points", static_cast<long>(d.samples.points), static_cast<long>(d.inside.points),
              static_cast<long>(d.image.points));
  std::printf("%-38s %14.3e\n", "Lagrange            max|w_i(c_j) - d_ij|", d.lagrange);
  std::printf("%-38s %14.3e\n", "linear precision on edges  max dev.", d.edgeLinearity);
  std::printf("\nlocality inside the cage (LBC eq. 19-21, every %d px):\n", d.pixelStep);
  for (std::size_t i = 0; i < d.locality.t.size(); ++i)
    std::printf("  P(%.0e) = %.3f   (mean fraction of the cage where |w_i| <= t)\n", d.locality.t[i], d.locality.P[i]);
  std::printf("  control points influencing a point (w > 1e-3/m): mean %.2f, max %d\n", d.locality.meanInfluencing,
              d.locality.maxInfluencing);
  for (std::size_t k = 1; k < d.locality.Q.size() && k <= 8; ++k) std::printf("  Q(%zu) = %.3f\n", k, d.locality.Q[k]);
  std::printf("\n%s\n", s.reports.summary().c_str());
  for (const std::string& p : s.reports.problems()) std::printf("  warning: %s\n", p.c_str());
  const app::BindTimings& t = s.timings;
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
    const app::BindTimings& t = s.timings;
    json j = {{"controls", s.cage.size()},
              {"samples", s.samples.size()},
              {"sigma", s.sigma},
              {"spacing", s.params.spacing},
              {"method", std::string(app::toString(s.params.kc.method))},
              {"init", std::string(app::toString(s.params.kc.init.method))},
              {"interp", std::string(app::toString(s.params.kc.interp))},
              {"properties",
               {{"samples", rowJson(d.samples)},
                {"inside", rowJson(d.inside)},
                {"image", rowJson(d.image)},
                {"lagrange", d.lagrange},
                {"edge_linearity", d.edgeLinearity}}},
              {"locality",
               {{"t", d.locality.t},
                {"P", d.locality.P},
                {"Q", d.locality.Q},
                {"mean_influencing", d.locality.meanInfluencing},
                {"max_influencing", d.locality.maxInfluencing}}},
              {"solver",
               {{"samples_optimized", s.reports.optimize.solved},
                {"outside_control_hull", s.reports.optimize.infeasible},
                {"not_optimal", s.reports.optimize.failed},
                {"max_iterations", s.reports.optimize.maxIterations},
                {"unreachable_targets", s.reports.init.fallbackSamples},
                {"unscreened_targets", s.reports.init.unscreenedSamples},
                {"sampling_converged", s.reports.sampling.converged},
                {"problems", s.reports.problems()}}},
              {"timings",
               {{"sampling", t.sampling}, {"assemble", t.assemble}, {"factor", t.factor}, {"init", t.init},
                {"optimize", t.optimize}, {"solve", t.solve}, {"total", t.total}, {"evaluate", d.evalSeconds}}}};
    std::cout << j.dump(2) << "\n";
  });
}

}  // namespace kc::cli
