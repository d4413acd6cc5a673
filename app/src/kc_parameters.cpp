// The kc backend's bind parameters (KcParams), described once: its flags, session keys and Bind
// panel widgets are made from this list. Its keys sit at the top of the session's params object
// (they predate parameter blocks); σ and the locality rule are written by its own
// writeParameters/readParameters (one key holds the σ used, two keys one rule).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "backends.h"
#include "json_util.h"
#include "kc/app/errors.h"
#include "kc/app/limits.h"
#include "kc/app/pipeline.h"
#include "kc/app/text.h"

namespace kc::app {
namespace {

using Type = BackendParameter::Type;
using Panel = BackendParameter::Panel;

BackendParameter named(const char* key, const char* label, const char* help, const char* tooltip) {
  BackendParameter p;
  p.key = key, p.label = label, p.help = help, p.tooltip = tooltip;
  return p;
}

BackendParameter boolean(BackendParameter p, bool defaultValue, bool (*get)(const BindParams&), void (*set)(BindParams&, bool)) {
  p.type = Type::Boolean;
  p.defaultValue = defaultValue ? 1.0 : 0.0;
  p.absentValue = 0.0;  // sessions written before each option: off
  p.panel = Panel::Advanced;
  p.get = [get](const BindParams& b) { return get(b) ? 1.0 : 0.0; };
  p.set = [set](BindParams& b, double v) { set(b, v != 0.0); };
  return p;
}

/// A number of the Advanced panel in [0, max] that only the QP reads; sessions written before it read 0.
BackendParameter qpNumber(BackendParameter p, double defaultValue, double max, double (*get)(const BindParams&),
                          void (*set)(BindParams&, double)) {
  p.min = 0.0, p.max = max;
  p.defaultValue = defaultValue;
  p.absentValue = 0.0;
  p.panel = Panel::Advanced;
  p.shownWhen = [](const BindParams& b) { return b.kc.method == Method::QP; };
  p.get = get;
  p.set = set;
  return p;
}

/// `params.locality`: the Pixels rule's length, −1 for the Automatic rule, 0 otherwise (off, or
/// the Spacings rule, which `params.locality_spacings` holds).
double localityPixels(const Locality& l) {
  switch (l.rule) {
    case Locality::Rule::Pixels:
      return l.value;
    case Locality::Rule::Automatic:
      return -1.0;
    default:
      return 0.0;
  }
}

std::vector<BackendParameter> describe() {
  const KcParams defaults;
  std::vector<BackendParameter> list;

  BackendParameter sigma = named("sigma", "sigma", "Kernel sigma in pixels (0 = automatic: 3T/pi, T the mean sample spacing)",
                                 "Smoothing width in pixels: larger gives smoother but less exact weights.");
  sigma.min = 0.0, sigma.max = kMaxCoordinate;
  sigma.defaultValue = defaults.sigma;
  sigma.stored = false;  // the session's `sigma` is the σ used; `sigma_auto` says whether it was chosen
  sigma.widget = "kernel-width";
  sigma.get = [](const BindParams& p) { return p.kc.sigma; };
  sigma.set = [](BindParams& p, double v) { p.kc.sigma = v; };
  list.push_back(sigma);

  BackendParameter init =
      named("init", "Initialization",
            ("Initial weights (lbc: local barycentric coordinates inside the cage, heat-linear outside, solved on a mesh of "
             "spacing --spacing / " +
             shortNumber(kLbcTargetSampling) +
             ", the automatic --spacing being that fraction of a heat-linear bind's; --lbc-* options apply)")
                .c_str(),
            "How the starting influences are guessed before they are optimized:\n"
            "heat-linear: heat spread from the cage outline, linear along its edges (recommended);\n"
            "heat-impulse: heat spread from the points only;\n"
            "inverse-distance: nearer points pull harder;\n"
            "lbc: the local influences of LBC inside the cage (as local as LBC, still paintable; slower Bind).");
  describeChoice(
      init, defaults.init.method, [](const BindParams& p) { return p.kc.init.method; },
      [](BindParams& p, InitMethod m) { p.kc.init.method = m; });
  list.push_back(init);

  BackendParameter iterations =
      named("heat_iterations", "Heat iterations",
            ("Heat diffusion iterations, 0.." + std::to_string(kMaxHeatIterations) + " (0 = converged steady state)").c_str(),
            "How many steps the heat spreads for; 0 (recommended): until it settles.");
  iterations.type = Type::Integer;
  iterations.min = 0, iterations.max = kMaxHeatIterations;
  iterations.defaultValue = defaults.init.iterations;
  iterations.panel = Panel::Advanced;
  iterations.shownWhen = [](const BindParams& p) { return p.kc.init.method != InitMethod::InverseDistance; };
  iterations.get = [](const BindParams& p) { return static_cast<double>(p.kc.init.iterations); };
  iterations.set = [](BindParams& p, double v) { p.kc.init.iterations = static_cast<int>(v); };
  list.push_back(iterations);

  // The Bind panel's switch over the two below and the floor: screened targets with their floor, or neither.
  BackendParameter local = named("local_targets", "Local targets", "",
                                 "A point pulls mostly on the parts of the shape near it (screened heat diffusion, its faint far "
                                 "tail dropped), about as locally as LBC (recommended). Off: smooth influences that reach "
                                 "further. Takes effect at the next Bind.");
  local.type = Type::Boolean;
  local.defaultValue = 1.0;
  local.flag = local.stored = false;
  local.widget = "local-targets";
  local.shownWhen = [](const BindParams& p) { return p.kc.init.method == InitMethod::HeatLinear; };
  local.get = [](const BindParams& p) { return p.kc.locality.rule != Locality::Rule::Off ? 1.0 : 0.0; };
  local.set = [](BindParams& p, double v) {
    p.kc.locality = v != 0.0 ? Locality{} : Locality{Locality::Rule::Off, 0.0};
    p.kc.targetFloor = v != 0.0 ? kTargetFloor : 0.0;
  };
  list.push_back(local);

  // The command line sets these two in this order: --locality, when given, replaces --locality-spacings.
  BackendParameter spacings =
      named("locality_spacings", "Locality (spacings)",
            "Screened heat-linear targets: locality length in sample spacings (0 = off: --locality decides)",
            "How far a point's pull reaches inside the shape, in sample spacings.");
  spacings.min = 0.0, spacings.max = kMaxCoordinate;
  spacings.accepts = "0 (off) or a positive number of spacings";
  spacings.defaultValue = defaults.locality.value;
  spacings.stored = false;
  spacings.panel = Panel::Hidden;  // the Local targets switch
  spacings.get = [](const BindParams& p) { return p.kc.locality.rule == Locality::Rule::Spacings ? p.kc.locality.value : 0.0; };
  spacings.set = [](BindParams& p, double v) {
    p.kc.locality = v > 0.0 ? Locality{Locality::Rule::Spacings, v} : Locality{Locality::Rule::Off, 0.0};
  };
  list.push_back(spacings);

  BackendParameter pixels = named("locality", "Locality",
                                  "Screened heat-linear targets: locality length in pixels (0 = off: global, harmonic-like "
                                  "targets; <0 = 5% of the cage diagonal); replaces --locality-spacings",
                                  "How far (pixels, inside the shape) a point's pull reaches; by default 1.5 sample spacings, "
                                  "more in a deep shape with few points.");
  pixels.min = -kMaxCoordinate, pixels.max = kMaxCoordinate;
  pixels.accepts = "a length in pixels (0 off, < 0 automatic)";
  pixels.defaultValue = 0.0;
  pixels.stored = false;
  pixels.panel = Panel::Hidden;  // the Local targets switch
  pixels.get = [](const BindParams& p) { return localityPixels(p.kc.locality); };
  pixels.set = [](BindParams& p, double v) {
    p.kc.locality = v > 0.0   ? Locality{Locality::Rule::Pixels, v}
                    : v < 0.0 ? Locality{Locality::Rule::Automatic, 0.0}
                              : Locality{Locality::Rule::Off, 0.0};
  };
  list.push_back(pixels);

  BackendParameter floor =
      named("target_floor", "Target floor",
            "Screened heat-linear targets: the heat below this weight is dropped before the optimization, so "
            "each point pulls on a smaller part of the shape (0 = off; below 0.5)",
            "Influence below this is dropped from the starting guess, so each point pulls on a smaller part "
            "of the shape (0: keep it all).");
  floor.min = 0.0, floor.max = kMaxTargetFloor, floor.openMax = true;
  floor.accepts = "in [0, 0.5) (0 = off)";
  floor.defaultValue = defaults.targetFloor;
  floor.absentValue = 0.0;  // sessions written before the option: the whole diffused tail
  floor.panel = Panel::Advanced;
  floor.shownWhen = [](const BindParams& p) {
    return p.kc.init.method == InitMethod::HeatLinear && p.kc.locality.rule != Locality::Rule::Off;
  };
  floor.get = [](const BindParams& p) { return p.kc.targetFloor; };
  floor.set = [](BindParams& p, double v) { p.kc.targetFloor = v; };
  list.push_back(floor);

  list.push_back(boolean(
      named("guard_lobes", "Guard lobes",
            "Keep the optimizer's weights outside next to the cage and the sampling at sharp outside corners "
            "(the field then dips deeper below 0 inside, next to the cage)",
            "Keeps the influences from dipping below zero inside, next to the cage (recommended)."),
      defaults.guardLobes, [](const BindParams& p) { return p.kc.guardLobes; },
      [](BindParams& p, bool v) { p.kc.guardLobes = v; }));

  BackendParameter lift = boolean(
      named("lift_lobes", "Lift lobes",
            "QP: raise the field's dips below 0 inside the cage (between the samples, where a weight falls to 0) "
            "with smooth bumps that keep partition of unity and reproduction",
            "Keeps the influences from dipping below zero between the sample points, so nothing moves against "
            "a drag (best with a target floor of 0.05)."),
      defaults.liftLobes, [](const BindParams& p) { return p.kc.liftLobes; }, [](BindParams& p, bool v) { p.kc.liftLobes = v; });
  lift.shownWhen = [](const BindParams& p) { return p.kc.method == Method::QP; };
  list.push_back(lift);

  // Sessions written before the option read 0: the field unbounded.
  BackendParameter bound = qpNumber(
      named("lobe_bound", "Lobe bound",
            "QP: the weights inside the cage stay >= -this value; where the field dips below it, its weights are "
            "projected back (partition of unity and reproduction kept; 0 = off)",
            "How far below zero an influence may dip inside the shape (0: no limit). With 0.0125, a 40 px drag moves "
            "nothing inside the shape half a pixel or more the wrong way."),
      defaults.lobeBound, kMaxLobeBound, [](const BindParams& p) { return p.kc.lobeBound; },
      [](BindParams& p, double v) { p.kc.lobeBound = v; });
  bound.accepts = "in [0, 0.5] (0 = off)";
  list.push_back(bound);

  BackendParameter method = named("method", "Method", "Optimization", "How the influences are optimized.");
  describeChoice(
      method, defaults.method, [](const BindParams& p) { return p.kc.method; }, [](BindParams& p, Method m) { p.kc.method = m; });
  method.panel = Panel::Hidden;  // switched live in the Weights panel
  list.push_back(method);

  // Sessions written before the option read 0: the Euclidean QP.
  list.push_back(qpNumber(
      named("qp_allowance", "Near correction",
            "QP metric: the change of a sample's weight on a control costs 1/(min(target, 10e) + e), e this value, so the "
            "correction that restores reproduction falls on the controls near the sample (0 = the thesis's plain QP)",
            "How strongly the optimizer keeps each point's pull to its own part of the shape when it corrects the "
            "influences (smaller: more local; 0: the thesis's plain optimization)."),
      defaults.qpAllowance, 1.0, [](const BindParams& p) { return p.kc.qpAllowance; },
      [](BindParams& p, double v) { p.kc.qpAllowance = v; }));

  BackendParameter interp = named("interp", "Interpolation", "Interpolation",
                                  "exact: influences add up to exactly 1 everywhere, so unmoved parts stay put (recommended);\n"
                                  "thesis: the plain kernel form of the thesis (about 0.1% off).");
  describeChoice(
      interp, defaults.interp, [](const BindParams& p) { return p.kc.interp; },
      [](BindParams& p, InterpMode m) { p.kc.interp = m; });
  list.push_back(interp);

  list.push_back(boolean(
      named("linear_edges", "Linear edges",
            "Post-process the samples near every edge of the cage's loops (not sticks) so that the field is "
            "linear along it, not only at its samples (thesis 5.3.3; deepens the negative lobes near the controls)",
            "Makes the influences exactly linear along every cage edge, so edges stay straight (deeper dips "
            "below zero near the points)."),
      defaults.linearEdges, [](const BindParams& p) { return p.kc.linearEdges; },
      [](BindParams& p, bool v) { p.kc.linearEdges = v; }));

  list.push_back(boolean(
      named("exact_lines", "Exact lines",
            "Keep structure lines straight by post-processing the samples near them (thesis 5.3.3) instead "
            "of the field's exact correction",
            "Keeps structure lines straight exactly (recommended); off: the thesis's post-processing of the "
            "samples near them."),
      defaults.exactLines, [](const BindParams& p) { return p.kc.exactLines; },
      [](BindParams& p, bool v) { p.kc.exactLines = v; }));
  return list;
}

}  // namespace

const std::vector<BackendParameter>& kcParameters() {
  static const std::vector<BackendParameter> described = describe();
  return described;
}

void writeKcParameters(const Session& s, nlohmann::json& params) {
  const KcParams& kc = s.params.kc;
  params["sigma_auto"] = !(kc.sigma > 0.0);
  params["locality"] = localityPixels(kc.locality);
  params["locality_spacings"] = kc.locality.rule == Locality::Rule::Spacings ? kc.locality.value : 0.0;
}

void readKcParameters(const nlohmann::json& params, Session& s, const std::string& where) {
  KcParams& kc = s.params.kc;
  const bool sigmaAuto = params.contains("sigma_auto") && params["sigma_auto"].is_boolean() && params["sigma_auto"].get<bool>();
  kc.sigma = sigmaAuto ? 0.0 : s.sigma;
  // `locality_spacings` > 0: the Spacings rule; else `locality` in pixels, < 0 automatic, 0 (or
  // absent, sessions written before either option) off.
  double spacings = 0.0, pixels = 0.0;
  if (params.contains("locality_spacings")) {
    spacings = detail::boundedNumber(params["locality_spacings"], kMaxCoordinate, where, "params.locality_spacings");
    if (!(spacings >= 0.0)) throw InputError(where, "params.locality_spacings must be 0 (off) or a positive number of spacings");
  }
  if (params.contains("locality")) pixels = detail::boundedNumber(params["locality"], kMaxCoordinate, where, "params.locality");
  kc.locality = spacings > 0.0 ? Locality{Locality::Rule::Spacings, spacings}
                : pixels > 0.0 ? Locality{Locality::Rule::Pixels, pixels}
                : pixels < 0.0 ? Locality{Locality::Rule::Automatic, 0.0}
                               : Locality{Locality::Rule::Off, 0.0};
}

}  // namespace kc::app
