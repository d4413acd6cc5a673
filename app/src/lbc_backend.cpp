// The local-barycentric-coordinates backend ("lbc"): cage → CGAL mesh of its interior → LBC
// weights by ADMM (core/lbc) → MeshField. No targets, methods or painting; no weights outside
// the cage (LBC paper §3–4, Appendix B).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <limits>
#include <vector>

#include <nlohmann/json.hpp>

#include "backends.h"
#include "json_util.h"
#include "kc/app/pipeline.h"
#include "kc/app/text.h"
#include "kc/core/field/mesh_field.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/lbc_solver.h"
#include "kc/core/timing.h"

namespace kc::app {
namespace {

/// Where each stage starts on the bind's progress bar: mesh, geodesics and factorizations, ADMM.
constexpr double kStageStart[] = {0.0, 0.05, 0.15};

/// Mesh vertices kcwarp accepts for one LBC bind (≈ 16 kB per vertex for 30 controls).
constexpr Index kMaxLbcVertices = 400'000;

/// The LBC solve of a bind (BackendReport): the solver's report and the mesh's size.
class LbcBindReport final : public BackendReport {
 public:
  LbcBindReport(const LbcReport& report, Index vertices) : m_r(report), m_vertices(vertices) {}

  Index meshVertices() const override { return m_vertices; }
  std::string summary() const override {
    const bool certified = std::isfinite(m_r.lowerBound) && m_r.lowerBound != 0.0;
    return format(
        "LBC on %ld vertices, %d ADMM iterations, residuals primal %.2e dual %.2e, objective %.6g (%s), %ld vertices "
        "projected to w >= 0",
        static_cast<long>(m_vertices), m_r.iterations, m_r.primalResidual, m_r.dualResidual, m_r.objective,
        certified ? format("certified within %.3g%% of the optimum",
                           100.0 * (m_r.objective - m_r.lowerBound) / std::abs(m_r.lowerBound))
                        .c_str()
                  : "no certified bound",
        static_cast<long>(m_r.projectedVertices));
  }
  std::vector<std::string> problems() const override {
    std::vector<std::string> out;
    if (m_r.status != SolveStatus::Ok)
      out.push_back(format("LBC: not converged after %d iterations (primal %.2e, dual %.2e)", m_r.iterations, m_r.primalResidual,
                           m_r.dualResidual));
    if (m_r.projectionFailures > 0)
      out.push_back(
          format("LBC: %ld vertices not projected to w >= 0 with certainty", static_cast<long>(m_r.projectionFailures)));
    return out;
  }
  std::string brief() const override {
    return format("%ld mesh vertices, %d iterations", static_cast<long>(m_vertices), m_r.iterations);
  }
  std::string details(const BindParams& params, const char* indent) const override {
    return format(
        "%sLBC solver: stops at residuals <= %s and a certified gap <= %s%%; objective %.6g (LBC eq. 14, picture "
        "scaled to diameter 1) >= lower bound %.6g; penalty %s; largest change by the projection to w >= 0 %.2e\n",
        indent, shortNumber(params.lbc.tolerance).c_str(), shortNumber(100.0 * params.lbc.gap).c_str(), m_r.objective,
        m_r.lowerBound, shortNumber(m_r.penalty).c_str(), m_r.maxProjection);
  }
  void toJson(nlohmann::json& j, bool session) const override {
    j = {{"mesh_vertices", m_vertices},
         {"converged", m_r.status == SolveStatus::Ok},
         {"iterations", m_r.iterations},
         {"primal_residual", m_r.primalResidual},
         {"dual_residual", m_r.dualResidual},
         {"penalty", m_r.penalty},
         {"objective", m_r.objective},
         {"lower_bound", m_r.lowerBound},
         {"projected_vertices", m_r.projectedVertices},
         {"max_projection", m_r.maxProjection}};
    if (!session) return;
    if (!std::isfinite(m_r.lowerBound)) j["lower_bound"] = nullptr;
    j["projection_failures"] = m_r.projectionFailures;
    j["seconds"] = {{"geodesics", m_r.geodesicSeconds},
                    {"factor", m_r.factorSeconds},
                    {"iterations", m_r.iterationSeconds},
                    {"certificate", m_r.certifySeconds}};
  }

  /// The report a session's reports.lbc object holds (missing or mistyped keys: their defaults).
  static std::shared_ptr<const BackendReport> fromJson(const nlohmann::json& j) {
    if (!j.is_object()) return nullptr;
    auto get = [&](const char* key, auto fallback) { return detail::valueOr(j, key, fallback); };
    LbcReport r;
    r.status = get("converged", false) ? SolveStatus::Ok : SolveStatus::NotConverged;
    r.iterations = get("iterations", 0);
    r.primalResidual = get("primal_residual", 0.0);
    r.dualResidual = get("dual_residual", 0.0);
    r.penalty = get("penalty", 0.0);
    r.objective = get("objective", 0.0);
    r.lowerBound = get("lower_bound", -std::numeric_limits<double>::infinity());
    r.projectedVertices = get("projected_vertices", Index{0});
    r.maxProjection = get("max_projection", 0.0);
    r.projectionFailures = get("projection_failures", Index{0});
    if (j.contains("seconds")) {
      const nlohmann::json& t = j["seconds"];
      r.geodesicSeconds = detail::valueOr(t, "geodesics", 0.0);
      r.factorSeconds = detail::valueOr(t, "factor", 0.0);
      r.iterationSeconds = detail::valueOr(t, "iterations", 0.0);
      r.certifySeconds = detail::valueOr(t, "certificate", 0.0);
    }
    return std::make_shared<LbcBindReport>(r, get("mesh_vertices", Index{0}));
  }

 private:
  LbcReport m_r;
  Index m_vertices = 0;
};

}  // namespace

LbcBind solveLbcForBind(const Cage& cage, const BindParams& params, const std::function<void(const char*, double)>& step) {
  const LbcParams& lbc = params.lbc;
  if (!(lbc.tolerance > 0.0)) throw std::invalid_argument("the LBC tolerance must be positive (--lbc-tolerance)");
  if (lbc.maxIterations < 1) throw std::invalid_argument("the LBC iteration cap must be at least 1 (--lbc-max-iterations)");

  // The uniform mesh's vertex count, refused before meshing (a graded mesh adds its narrow places).
  const double estimate = estimateMeshVertices(cage, params.spacing);
  if (estimate > double(kMaxLbcVertices))
    throw std::invalid_argument("the LBC mesh of this cage at spacing " + shortNumber(params.spacing) + " px would have about " +
                                shortNumber(estimate) + " vertices, more than kcwarp's limit of " + std::to_string(kMaxLbcVertices) +
                                "; use a larger --spacing");
  step("mesh", 0.0);
  LbcBind b;
  auto t0 = std::chrono::steady_clock::now();
  CageMeshOptions mo;
  mo.spacing = params.spacing;
  mo.maxVertices = kMaxLbcVertices;
  mo.sizing = bindSizing(cage, Structure{}, params);
  b.mesh = meshCageInterior(cage, mo);
  b.sizing = mo.sizing;
  if (b.mesh.status != SolveStatus::Ok)
    throw std::invalid_argument("the LBC mesh of this cage at spacing " + shortNumber(params.spacing) + " px would have more than " +
                                std::to_string(kMaxLbcVertices) + " vertices; use a larger --spacing");
  b.meshSeconds = secondsSince(t0);

  step("geodesics", kStageStart[1]);
  const LbcSolver solver(b.mesh, lbc.tau);
  LbcOptions options;
  options.tau = lbc.tau;
  options.tolerance = lbc.tolerance;
  options.maxIterations = lbc.maxIterations;
  options.gapTolerance = lbc.gap;
  options.progress = [&](double f) {
    step("LBC iterations", kStageStart[2] + (1.0 - kStageStart[2]) * f);  // throws kc::Cancelled to stop
    return true;
  };
  step("LBC iterations", kStageStart[2]);
  b.result = solver.solve(options);
  const LbcReport& rep = b.result.report;
  if (rep.status == SolveStatus::Singular)
    throw std::invalid_argument("the LBC system of this cage's mesh cannot be factorized (degenerate triangles); "
                                "try another --spacing");
  if (rep.status == SolveStatus::NotConverged)
    throw std::invalid_argument("LBC did not converge within " + std::to_string(rep.iterations) + " iterations (residuals " +
                                shortNumber(rep.primalResidual) + ", " + shortNumber(rep.dualResidual) + ", tolerance " + shortNumber(lbc.tolerance) +
                                "); raise the iteration cap (--lbc-max-iterations; the Bind panel's Max iterations) or the tolerance "
                                "(--lbc-tolerance; LBC tolerance)");
  return b;
}

namespace {

class LbcBackend final : public Backend {
 public:
  std::string_view name() const override { return "lbc"; }
  std::string_view displayName() const override { return "LBC"; }
  std::string_view description() const override {
    return "local barycentric coordinates on a mesh of the cage interior, edge length --spacing; no weights outside the cage: "
           "warps cannot use --outside deform";
  }
  std::string_view tooltip() const override {
    return "Local barycentric coordinates (LBC paper): each point pulls only on the part of the shape near it. Computed once "
           "on a triangle mesh of the cage's inside: no brush, no method switch, and no influence outside the cage (the "
           "outside is kept or pinned).";
  }
  std::string_view parameterBlock() const override { return "lbc"; }

  const std::vector<BackendParameter>& parameters() const override {
    static const std::vector<BackendParameter> described = describe();
    return described;
  }

 private:
  /// The tau, tolerance, iteration cap and optimality gap of LbcParams, described once (parameters()).
  static std::vector<BackendParameter> describe() {
    using Type = BackendParameter::Type;
    const LbcParams defaults;
    const auto named = [](const char* key, const char* label, const char* help, const char* tooltip) {
      BackendParameter p;
      p.key = key, p.label = label, p.help = help, p.tooltip = tooltip;
      return p;
    };
    std::vector<BackendParameter> list{
        named("tau", "LBC locality", "LBC locality weighting tau(D) of the geodesic distance",
              "How strongly an influence far from its point is penalized (tau of the distance inside the shape, LBC eq. "
              "11): square: most local (recommended); linear and sqrt: less local; const: no distance weighting."),
        named("tolerance", "LBC tolerance", "LBC stopping rule: RMS primal and dual ADMM residuals (per unit area)",
              "When the solver may stop: its residuals (RMS per point, picture scaled to size 1) below this, and the result "
              "certified within the optimality gap of the best possible. Smaller: slower, barely different (default 1e-3)."),
        named("max_iterations", "Max iterations", "LBC iteration cap (not converged by then: the bind fails)",
              "The solver gives up after this many iterations and Bind reports it (default 20000)."),
        named(
            "gap", "LBC optimality gap",
            "LBC stopping rule: the weights' objective (LBC eq. 14) certified within this fraction of the optimum",
            "How close to the best possible weights the solver must prove it is before it stops: 0.01 = within 1% "
            "(default: weights within a few hundredths of the best); 0.001 = within 0.1%, several times slower on a tight cage.")};
    describeChoice(
        list[0], defaults.tau, [](const BindParams& p) { return p.lbc.tau; }, [](BindParams& p, LbcTau t) { p.lbc.tau = t; });
    BackendParameter& tolerance = list[1];
    tolerance.min = 1e-12, tolerance.max = 1.0, tolerance.logarithmic = true;
    tolerance.defaultValue = defaults.tolerance;
    tolerance.get = [](const BindParams& p) { return p.lbc.tolerance; };
    tolerance.set = [](BindParams& p, double v) { p.lbc.tolerance = v; };
    BackendParameter& iterations = list[2];
    iterations.type = Type::Integer;
    iterations.min = 1, iterations.max = 100'000'000;
    iterations.defaultValue = static_cast<double>(defaults.maxIterations);
    iterations.get = [](const BindParams& p) { return static_cast<double>(p.lbc.maxIterations); };
    iterations.set = [](BindParams& p, double v) { p.lbc.maxIterations = static_cast<int>(v); };
    BackendParameter& gap = list[3];
    gap.min = 1e-6, gap.max = 1.0, gap.logarithmic = true;
    gap.defaultValue = defaults.gap;
    gap.absentValue = 0.001;  // files written before the parameter: the solver's 0.1% then
    gap.panel = BackendParameter::Panel::Advanced;
    gap.get = [](const BindParams& p) { return p.lbc.gap; };
    gap.set = [](BindParams& p, double v) { p.lbc.gap = v; };
    return list;
  }

 public:
  BackendCapabilities capabilities() const override {
    BackendCapabilities c;
    c.why = "LBC weights are solved once on a mesh of the cage interior: there are no per-sample target weights to "
            "paint or re-optimize, and no weights outside the cage";
    return c;
  }

  void bind(Session& s, const BindStep& step) const override {
    LbcBind b = solveLbcForBind(s.cage, s.params, step);
    BindReport& r = s.report;
    const CageMesh& mesh = b.mesh;
    const LbcReport& rep = b.result.report;
    r.sampling = {};
    r.sampling.controls = mesh.controls;
    r.sampling.edge = mesh.boundary - mesh.controls;
    r.sampling.interior = mesh.interior();
    r.sampling.seconds = b.meshSeconds;
    r.factor = {};
    r.factor.status = SolveStatus::Ok;
    r.factor.factorSeconds = rep.factorSeconds;
    r.init = {};
    r.init.seconds = rep.geodesicSeconds;
    r.optimize = {};
    r.optimize.solved = mesh.size();
    r.optimize.maxIterations = rep.iterations;
    r.optimize.failed = rep.projectionFailures;
    r.optimize.seconds = rep.iterationSeconds;
    r.backend = std::make_shared<LbcBindReport>(rep, mesh.size());

    s.sigma = 0.0;
    s.sizing = b.sizing;
    s.samples.X = mesh.V;
    s.samples.kind.assign(std::size_t(mesh.size()), SampleKind::Interior);
    for (Index v = 0; v < mesh.boundary; ++v) s.samples.kind[std::size_t(v)] = v < mesh.controls ? SampleKind::Control : SampleKind::Edge;
    s.samples.edge = mesh.edge;
    s.W0.resize(0, 0);
    s.W = b.result.W;
    s.field = std::make_unique<MeshField>(mesh.V, mesh.T, std::move(b.result.W));
  }

  std::shared_ptr<const BackendReport> readReport(const nlohmann::json& block) const override {
    return LbcBindReport::fromJson(block);
  }

  void rebuildField(Session& s) const override {
    throw std::invalid_argument("an LBC session must carry its mesh (the \"field\" block with kind \"mesh\"); bind it again");
  }

  OptimizeReport reoptimize(Session&, Method, std::span<const Index>, std::vector<Index>*) const override {
    throw std::invalid_argument("LBC sessions cannot be re-optimized: " + capabilities().why);
  }
};

}  // namespace

const Backend& lbcBackend() {
  static const LbcBackend lbc;
  return lbc;
}

}  // namespace kc::app
