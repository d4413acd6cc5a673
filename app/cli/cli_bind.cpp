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
  double spacing = kDefaults.spacing, margin = kDefaults.margin;
  std::string backend = kDefaults.backend, sampler = nameOf(kDefaults.sampler);
  std::string exterior = nameOf(kDefaults.exterior);
  bool uniformSpacing = !kDefaults.graded;
  std::uint64_t seed = kDefaults.seed;
  CLI::Option* spacingOption = nullptr;  // given or not: without it the spacing is automatic
  /// The backends' described parameters (app::parameterFlag), in the order they describe them:
  /// the text given (the default's when not; a Boolean's flag: whether it was given) and the
  /// option, which says whether it was given.
  struct BackendOption {
    const app::Backend* backend = nullptr;
    const app::BackendParameter* parameter = nullptr;
    std::string text;
    bool on = false;
    CLI::Option* option = nullptr;
  };
  std::vector<BackendOption> backendOptions;
};

/// Sets the backends' parameters given on the command line, in the order each backend describes
/// them (each refused with its flag's name).
void setBackendParameters(const BindArgs& a, app::BindParams& p) {
  for (const BindArgs::BackendOption& o : a.backendOptions) {
    if (o.option->count() == 0) continue;
    const app::BackendParameter& parameter = *o.parameter;
    const std::string flag = app::parameterFlag(*o.backend, parameter);
    std::optional<double> value;
    if (parameter.type == app::BackendParameter::Type::Boolean) value = parameter.defaultValue != 0.0 ? 0.0 : 1.0;
    else value = app::parseParameter(parameter, o.text);
    if (!value && parameter.type == app::BackendParameter::Type::Choice) {
      std::string list;
      for (const std::string& c : parameter.choices) list += (list.empty() ? "" : ", ") + c;
      throw app::InputError(flag, "unknown value '" + o.text + "' (accepted: " + list + ")");
    }
    if (!value) throw app::InputError(flag, "must be " + app::parameterRange(parameter));
    app::asUserInput(flag, [&] { app::setParameter(*o.backend, parameter, p, *value); });
  }
}

/// A flag for each described parameter of each backend (app::parameterFlag), its default shown.
void addBackendOptions(CLI::App* sub, BindArgs* a) {
  std::size_t count = 0;
  for (const std::string_view name : app::backendNames()) count += app::backendFor(name).parameters().size();
  a->backendOptions.reserve(count);  // the options hold pointers into the list
  for (const std::string_view name : app::backendNames()) {
    const app::Backend& backend = app::backendFor(name);
    for (const app::BackendParameter& parameter : backend.parameters()) {
      if (!parameter.flag) continue;
      const std::string flag = app::parameterFlag(backend, parameter);
      BindArgs::BackendOption& o = a->backendOptions.emplace_back();
      o.backend = &backend;
      o.parameter = &parameter;
      if (parameter.type == app::BackendParameter::Type::Boolean) {
        o.option = sub->add_flag(flag, o.on, parameter.help);
        continue;
      }
      std::string help = parameter.help;
      if (parameter.type == app::BackendParameter::Type::Choice) {
        help += ":";
        for (std::size_t k = 0; k < parameter.choices.size(); ++k) help += (k ? " | " : " ") + parameter.choices[k];
      }
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
  requireFinite(a.margin, "--margin");
  // Only the picture's size is needed: its header, checked against the limits, not its pixels
  // (decoding a 12 MP PNG took longer than the bind itself; warp decodes it).
  const auto [w, h] = a.image.empty() ? parseSize(a.size, "--size") : imageHeaderSize(a.image);
  app::BindParams p;
  p.spacing = a.spacing;
  p.margin = a.margin;
  p.seed = a.seed;
  p.backend = a.backend;
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
    if (r.lift.rounds > 0)
      std::printf("lobes: %ld lifted, deepest weight inside %.3g -> %.3g (%.3f s)\n", static_cast<long>(r.lift.lobes),
                  r.lift.deepestBefore, r.lift.deepestAfter, r.lift.seconds);
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
  a->spacingOption =
      sub->add_option("--spacing", a->spacing,
                      "Sample spacing h in pixels (default: 6, or larger for big cages so the kc backend "
                      "samples about " +
                          std::to_string(int(app::kAutoSpacingSamples)) + " points over the cage and a band around it)");
  sub->add_flag("--uniform-spacing", a->uniformSpacing,
                "One spacing everywhere (the default grades it: finer at the cage's narrow places, down to what the "
                "narrowest needs; narrow places then need --spacing at most their width)");
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
