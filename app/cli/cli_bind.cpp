// kcwarp-cli bind: cage + image → session file (samples, W0, W).

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/structure.h"
#include "kc/app/limits.h"
#include "kc/app/pipeline.h"
#include "kc/app/text.h"

namespace kc::cli {
namespace {

/// The defaults of every option: app::BindParams' own.
const app::BindParams kDefaults{};

struct BindArgs {
  std::string cage, image, size, output, structure;
  double spacing = kDefaults.spacing, sigma = kDefaults.kc.sigma, margin = kDefaults.margin;
  std::string init = nameOf(kDefaults.kc.init.method), method = nameOf(kDefaults.kc.method), interp = nameOf(kDefaults.kc.interp),
              backend = kDefaults.backend, sampler = nameOf(kDefaults.sampler);
  std::string exterior = nameOf(kDefaults.exterior);
  int heatIterations = kDefaults.kc.init.iterations;
  bool linearEdges = kDefaults.kc.linearEdges;
  bool uniformSpacing = !kDefaults.graded;
  double locality = 0.0;  // --locality, when given, replaces --locality-spacings
  double localitySpacings = kDefaults.kc.locality.value;
  double targetFloor = kDefaults.kc.targetFloor;
  bool noGuardLobes = !kDefaults.kc.guardLobes;
  CLI::Option* localityOption = nullptr;  // given: the locality length in pixels replaces --locality-spacings
  std::uint64_t seed = kDefaults.seed;
  CLI::Option* spacingOption = nullptr;  // given or not: without it the spacing is automatic
  /// The backends' described parameters (--<block>-<key>), by "<backend>\n<key>": the text given
  /// (the default's when not) and the option, which says whether it was given.
  struct BackendOption {
    std::string text;
    CLI::Option* option = nullptr;
  };
  std::map<std::string, BackendOption> backendOptions;
};

/// Sets the backends' parameters given on the command line (each refused with its flag's name).
void setBackendParameters(const BindArgs& a, app::BindParams& p) {
  for (const std::string_view name : app::backendNames()) {
    const app::Backend& backend = app::backendFor(name);
    for (const app::BackendParameter& parameter : backend.parameters()) {
      const std::string id = std::string(name) + "\n" + parameter.key;
      const auto found = a.backendOptions.find(id);
      if (found == a.backendOptions.end() || found->second.option->count() == 0) continue;
      const std::string flag = found->second.option->get_name();
      const std::optional<double> value = app::parseParameter(parameter, found->second.text);
      if (!value) throw app::InputError(flag, "must be " + app::parameterRange(parameter));
      app::asUserInput(flag, [&] { app::setParameter(backend, parameter, p, *value); });
    }
  }
}

/// --<block>-<key> for each described parameter of each backend, its default shown.
void addBackendOptions(CLI::App* sub, BindArgs* a) {
  for (const std::string_view name : app::backendNames()) {
    const app::Backend& backend = app::backendFor(name);
    for (const app::BackendParameter& parameter : backend.parameters()) {
      std::string flag = "--" + std::string(backend.parameterBlock()) + "-" + parameter.key;
      std::replace(flag.begin(), flag.end(), '_', '-');
      const std::string id = std::string(name) + "\n" + parameter.key;
      std::string help = parameter.help;
      if (parameter.type == app::BackendParameter::Type::Choice) {
        help += ":";
        for (std::size_t k = 0; k < parameter.choices.size(); ++k) help += (k ? " | " : " ") + parameter.choices[k];
      }
      BindArgs::BackendOption& o = a->backendOptions[id];
      o.text = app::parameterText(parameter, parameter.defaultValue);
      const char* type = parameter.type == app::BackendParameter::Type::Number    ? "FLOAT"
                         : parameter.type == app::BackendParameter::Type::Integer ? "INT"
                                                                                  : "TEXT";
      o.option = sub->add_option(flag, o.text, help)->type_name(type)->capture_default_str();
    }
  }
}

void runBind(const BindArgs& a) {
  const Cage cage = app::loadCage(a.cage);
  app::checkOutputFile(a.output);
  requireFinite(a.spacing, "--spacing");
  requireFinite(a.sigma, "--sigma");
  requireFinite(a.locality, "--locality");
  requireFinite(a.margin, "--margin");
  // Only the picture's size is needed: its header, checked against the limits, not its pixels
  // (decoding a 12 MP PNG took longer than the bind itself; warp decodes it).
  const auto [w, h] = a.image.empty() ? parseSize(a.size, "--size") : imageHeaderSize(a.image);
  app::BindParams p;
  p.spacing = a.spacing;
  p.kc.sigma = a.sigma;
  p.margin = a.margin;
  p.seed = a.seed;
  p.backend = a.backend;
  p.kc.init.method = parseOption<InitMethod>(a.init, "--init");
  p.kc.init.iterations = a.heatIterations;
  requireFinite(a.localitySpacings, "--locality-spacings", "spacings");
  if (a.localitySpacings < 0.0) throw app::InputError("--locality-spacings", "must be 0 (off) or a positive number of spacings");
  using Rule = app::Locality::Rule;
  if (a.localityOption && *a.localityOption)
    p.kc.locality = a.locality > 0.0   ? app::Locality{Rule::Pixels, a.locality}
                    : a.locality < 0.0 ? app::Locality{Rule::Automatic, 0.0}
                                       : app::Locality{Rule::Off, 0.0};
  else
    p.kc.locality = a.localitySpacings > 0.0 ? app::Locality{Rule::Spacings, a.localitySpacings} : app::Locality{Rule::Off, 0.0};
  if (!(a.targetFloor >= 0.0 && a.targetFloor < app::kMaxTargetFloor))  // also NaN
    throw app::InputError("--target-floor", "must be in [0, 0.5) (0 = off)");
  p.kc.targetFloor = a.targetFloor;
  p.kc.guardLobes = !a.noGuardLobes;
  p.kc.method = parseOption<Method>(a.method, "--method");
  p.kc.interp = parseOption<InterpMode>(a.interp, "--interp");
  p.kc.linearEdges = a.linearEdges;
  p.graded = !a.uniformSpacing;
  p.sampler = parseOption<sampling::SamplerKind>(a.sampler, "--sampler");
  p.exterior = parseOption<sampling::ExteriorExtent>(a.exterior, "--exterior");
  setBackendParameters(a, p);
  app::asUserInput("--backend", [&] { app::backendFor(p.backend); });
  app::Structure st;  // read before anything is printed: a bad file stops the bind with its one message
  if (!a.structure.empty()) {
    st = app::loadStructure(a.structure);
    if (const std::string refusal = app::structureRefusal(st, app::backendFor(p.backend)); !refusal.empty())
      throw app::InputError(a.structure, refusal);
  }
  if (a.spacingOption && a.spacingOption->count() == 0) {
    p.spacing = app::automaticSpacing(cage, w, h, p);
    if (const double mesh = app::weightSpacing(p); mesh != p.spacing)  // the kc backend's LBC targets
      std::printf(
          "spacing: automatic %.3g px, the LBC mesh %.3g px (a sample budget of %.0f over the cage and a band around it "
          "sets the mesh; the samples are %.3g times as far apart; --spacing overrides)\n",
          p.spacing, mesh, app::kAutoSpacingSamples, p.spacing / mesh);
    else if (p.spacing != a.spacing && !app::backendFor(p.backend).capabilities().outsideCage)
      std::printf("spacing: automatic %.3g px (an %s mesh of about %.0f vertices over the cage interior; --spacing overrides)\n",
                  p.spacing, std::string(app::backendFor(p.backend).displayName()).c_str(), app::kAutoLbcVertices);
    else if (p.spacing != a.spacing)
      std::printf("spacing: automatic %.3g px (a sample budget of %.0f over the cage and a band around it; --spacing overrides)\n",
                  p.spacing, app::kAutoSpacingSamples);
  }
  if (const std::string warning = app::backendFor(p.backend).narrowPlaceWarning(cage, p); !warning.empty()) {
    std::fflush(stdout);
    std::fprintf(stderr, "kcwarp-cli: warning: %s\n", warning.c_str());
  }

  kc::StageProgress progress;
  if (stderrIsTerminal())
    progress = [](const char* stage, double f) {
      std::fprintf(stderr, "\r%-20s %3.0f%%", stage, 100.0 * f);
      if (f >= 1.0) std::fprintf(stderr, "\n");
      return true;
    };
  if (!a.structure.empty())
    app::checkStructure(st, cage, p.spacing, a.structure, app::gradedSampling(p) || app::exactLines(p));
  app::Session s = app::bind(cage, st, w, h, p, progress);
  const app::BindReport& r = s.report;
  if (!a.image.empty()) s.image = app::imagePathForSession(a.image, a.output);
  app::releaseFactorization(s);  // not needed to save: the save's text then never meets the factor in memory
  app::saveSession(a.output, s);

  if (r.meshVertices() > 0) {
    const app::Backend& backend = app::backendFor(p.backend);
    std::printf("bound %ld control points, %s mesh of %ld vertices (%ld on the cage), %s\n", static_cast<long>(cage.size()),
                std::string(backend.displayName()).c_str(), static_cast<long>(s.samples.size()),
                static_cast<long>(r.sampling.controls + r.sampling.edge), app::parametersText(backend, p).c_str());
    if (s.sizing)
      std::printf("graded: mesh spacing %.3g-%.3g px for the cage's narrow places\n", s.sizing->hMin(), s.sizing->hMax());
    std::printf("%s\n", r.summary().c_str());
  } else if (app::backendFor(p.backend).capabilities().targets) {  // kernel coordinates: σ and the method
    std::printf("bound %ld control points, %ld samples (%ld edge, %ld interior, %ld exterior), sigma %.4g px\n",
                static_cast<long>(cage.size()), static_cast<long>(s.samples.size()), static_cast<long>(r.sampling.edge),
                static_cast<long>(r.sampling.interior), static_cast<long>(r.sampling.exterior), s.sigma);
    if (s.sizing)
      std::printf("graded: spacing %.3g-%.3g px (sigma %.3g-%.3g px) for the cage's narrow places\n", s.sizing->hMin(),
                  s.sizing->hMax(), s.sigma * s.sizing->hMin() / s.sizing->hMax(), s.sigma);
    std::printf("method %s, %s\n", std::string(app::toString(p.kc.method)).c_str(), r.summary().c_str());
  } else {
    std::printf("bound %ld control points with %s, %ld points\n%s\n", static_cast<long>(cage.size()),
                std::string(app::backendFor(p.backend).displayName()).c_str(), static_cast<long>(s.samples.size()),
                r.summary().c_str());
  }
  const app::BindTimings& t = r.timings;
  if (!st.rigid.empty())
    std::printf("rigid: %zu regions, %ld samples, rigidity energy %.4g -> %.4g (%ld nodes, %ld controls, %d %s%s, %.3f s)\n",
                st.rigid.size(), static_cast<long>(r.rigidity.region), r.rigidity.energyBefore, r.rigidity.energyAfter,
                static_cast<long>(r.rigidity.nodes), static_cast<long>(r.rigidity.controls), r.rigidity.solver.iterations,
                r.rigidity.solver.method != RigidityQpMethod::ActiveSet ? "ADMM iterations" : "active-set rounds",
                r.rigidity.solver.converged ? "" : ", NOT converged", r.rigidity.seconds);
  if (!st.lines.empty() && app::exactLines(s.params))
    std::printf("lines: %zu, kept straight by the field's correction: weights linear along them to %.2e (%.2e without it, %.3f s)\n",
                st.lines.size(), r.lines.after, r.lines.before, r.lines.seconds);
  else if (!st.lines.empty())
    std::printf("lines: %zu, field linear along them to %.2e (was %.2e; %ld samples adjusted, %.3f s)\n", st.lines.size(),
                r.lines.after, r.lines.before, static_cast<long>(r.lines.adjusted), r.lines.seconds);
  std::printf("time: sampling %.3f s, kernel %.3f s, factor %.3f s, init %.3f s, optimize %.3f s, solve %.3f s, total %.3f s\n",
              t.sampling, t.assemble, t.factor, t.init, t.optimize, t.solve, t.total);
  std::printf("wrote %s\n", a.output.c_str());
}

}  // namespace

void addBindCommand(CLI::App& app) {
  auto a = std::make_shared<BindArgs>();
  CLI::App* sub = app.add_subcommand("bind", "Sample the cage and image, compute and optimize weights, write a session");
  sub->add_option("--cage", a->cage, "Cage file (JSON)")->required();
  auto* image = sub->add_option("--image", a->image, "Image the cage is drawn over (gives the domain size)");
  auto* size = sub->add_option("--size", a->size, "Domain size W,H in pixels (instead of --image)");
  image->excludes(size);
  a->spacingOption = sub->add_option("--spacing", a->spacing,
                                     "Sample spacing h in pixels (default: 6, or larger for big cages so the kc backend "
                                     "samples about " + std::to_string(int(app::kAutoSpacingSamples)) +
                                         " points over the cage and a band around it)");
  sub->add_option("--sigma", a->sigma, "Kernel sigma in pixels (0 = automatic: 3T/pi, T the mean sample spacing)")->capture_default_str();
  sub->add_option("--init", a->init,
                  "Initial weights: heat-linear | heat-impulse | inverse-distance | lbc (local barycentric coordinates inside the "
                  "cage, heat-linear outside, solved on a mesh of spacing --spacing / " + app::shortNumber(app::kLbcTargetSampling) +
                  ", the automatic --spacing being that fraction of a heat-linear bind's; --lbc-* options apply)")
      ->capture_default_str();
  sub->add_option("--heat-iterations", a->heatIterations,
                  "Heat diffusion iterations, 0.." + std::to_string(app::kMaxHeatIterations) + " (0 = converged steady state)")
      ->check(CLI::Range(0, app::kMaxHeatIterations))
      ->capture_default_str();
  a->localityOption = sub->add_option("--locality", a->locality,
                  "Screened heat-linear targets: locality length in pixels (0 = off: global, harmonic-like targets; <0 = 5% of the cage "
                  "diagonal); replaces --locality-spacings");
  sub->add_option("--locality-spacings", a->localitySpacings,
                  "Screened heat-linear targets: locality length in sample spacings (0 = off: --locality decides)")
      ->capture_default_str();
  sub->add_option("--target-floor", a->targetFloor,
                  "Screened heat-linear targets: the heat below this weight is dropped before the optimization, so each "
                  "point pulls on a smaller part of the shape (0 = off; below 0.5)")
      ->capture_default_str();
  sub->add_flag("--no-guard-lobes", a->noGuardLobes,
                "Keep the optimizer's weights outside next to the cage and the sampling at sharp outside corners (the field then "
                "dips deeper below 0 inside, next to the cage)");
  sub->add_option("--method", a->method, "Optimization: qp | qec | l1")->capture_default_str();
  sub->add_option("--interp", a->interp, "Interpolation: exact | thesis")->capture_default_str();
  sub->add_flag("--uniform-spacing", a->uniformSpacing,
                "One spacing everywhere (the default grades it: finer at the cage's narrow places, down to what the "
                "narrowest needs; narrow places then need --spacing at most their width)");
  sub->add_flag("--linear-edges", a->linearEdges,
                "Post-process the samples near every edge of the cage's loops (not sticks) so that the field is linear "
                "along it, not only at its samples (thesis 5.3.3; deepens the negative lobes near the controls)");
  std::string backends;
  for (const std::string_view name : app::backendNames())
    backends +=
        (backends.empty() ? "" : " | ") + std::string(name) + " (" + std::string(app::backendFor(name).description()) + ")";
  sub->add_option("--backend", a->backend, "Weight backend: " + backends)->capture_default_str();
  addBackendOptions(sub, a.get());
  sub->add_option("--sampler", a->sampler, "Sampling: blue-noise | grid")->capture_default_str();
  sub->add_option("--margin", a->margin, "Sampled margin around the image in pixels (<0 = automatic)");
  sub->add_option("--exterior", a->exterior,
                  "How far outside the cage to sample: band (the cage's bounding box grown by " +
                      std::to_string(int(sampling::kExteriorBandSpacings)) +
                      " spacings; enough for --outside pinned, fixed and transparent) | frame (the whole picture: "
                      "needed by warp --outside deform)")
      ->capture_default_str();
  sub->add_option("--seed", a->seed, "Random seed of the sampling (0..2^64-1)")->check(seedCheck())->capture_default_str();
  sub->add_option("--structure", a->structure,
                  "Structure file (JSON): line segments kept straight, groups kept parallel (kc backend)");
  sub->add_option("-o,--output", a->output, "Session file to write (*.kcw.json)")->required();
  sub->callback([a] {
    if (a->image.empty() && a->size.empty()) throw app::InputError("bind", "give --image I.png or --size W,H");
    runBind(*a);
  });
}

}  // namespace kc::cli
