// The kernel-coordinate backend ("kc"): samples → K → W0 → W → KernelField (thesis ch. 3–6).

#include <algorithm>
#include <iterator>
#include <chrono>
#include <functional>
#include <numeric>
#include <utility>
#include <vector>
#include <stdexcept>
#include <string>

#include "backends.h"
#include "kc/core/structure/line_blend.h"
#include "kc/app/pipeline.h"
#include "kc/core/field/kernel_field.h"
#include "kc/core/field/lobe_lift.h"
#include "kc/core/field/mesh_field.h"
#include "kc/sampling/sigma.h"
#include "kc/core/timing.h"

namespace kc::app {
namespace {

/// Where each stage starts on the bind's progress bar (sampling, kernel, initial weights,
/// factorization, optimization, interpolation), roughly proportional to measured stage times.
constexpr double kStageStart[] = {0.0, 0.5, 0.6, 0.72, 0.9, 0.95};

/// The kernel of a session: σ and the scale for the spacing, with the width following the sizing
/// field of a graded sampling (GaussianKernel).
GaussianKernel kernelFor(double sigma, double spacing, const std::shared_ptr<const SizingField>& sizing) {
  GaussianKernel k = GaussianKernel::forSpacing(sigma, spacing);
  k.width = sizing;
  return k;
}

/// The field interpolates s.W: w(x_j) = W_j at every sample (|difference| ≤ 1e-6) and, in exact
/// mode, its kernel part is orthogonal to the polynomial (Σ_j U_j = 0, Σ_j x_j U_j = 0 up to
/// 1e-9 of Σ|U_j|·|x_j|) — together they determine [B; U] from W (the augmented system of 6.2 is
/// non-singular), so coefficients that pass are those a solve would give, up to round-off.
bool reproducesWeights(const KernelField& field, const Session& s) {
  if (field.controls() != s.W.cols() || field.nodes() != KernelField::kPolynomialNodes + s.W.rows()) return false;
  // The field without its lobe lift (which moves the weights near the lobes' samples) interpolates W.
  const bool lifted = field.lift().size() > 0;
  const RowMatrix U = lifted ? RowMatrix(field.kernelCoefficients().U - field.lift()) : field.kernelCoefficients().U;
  const Weights W =
      lifted ? Weights(field.weightsAt(s.samples.X) - field.evaluationOperator(s.samples.X).rightCols(U.rows()) * field.lift())
             : field.weightsAt(s.samples.X);
  if (!((W - s.W).cwiseAbs().maxCoeff() <= 1e-6)) return false;
  if (field.interpolator().mode() != InterpMode::Exact) return true;
  const Points& X = s.samples.X;
  for (int d = 0; d < 3; ++d) {
    const Eigen::VectorXd x = d == 0 ? Eigen::VectorXd::Ones(X.rows()) : Eigen::VectorXd(X.col(d - 1));
    const Eigen::RowVectorXd sum = x.transpose() * U, scale = x.cwiseAbs().transpose() * U.cwiseAbs();
    for (Index k = 0; k < U.cols(); ++k)
      if (!(std::abs(sum(k)) <= 1e-9 * scale(k) + 1e-12)) return false;
  }
  return true;
}

/// `--init lbc`: the targets W0 of the samples inside the cage (controls, edge and interior
/// samples) become the LBC weights there (solved on a mesh of the cage interior whose spacing is
/// the bind's divided by kLbcTargetSampling, barycentric interpolation between mesh vertices);
/// exterior samples keep theirs.
void lbcTargetsInside(Session& s, const std::function<void(const char*, double)>& step) {
  BindParams mesh = s.params;
  mesh.spacing = weightSpacing(s.params);
  s.lbcMeshSpacing = mesh.spacing;
  LbcBind b = solveLbcForBind(s.cage, mesh, step);
  const MeshField lbc(b.mesh.V, b.mesh.T, std::move(b.result.W));
  std::vector<Index> inside;
  for (Index i = 0; i < s.samples.size(); ++i)
    if (s.samples.kind[std::size_t(i)] != SampleKind::Exterior) inside.push_back(i);
  Points P(Index(inside.size()), 2);
  for (std::size_t k = 0; k < inside.size(); ++k) P.row(Index(k)) = s.samples.X.row(inside[k]);
  const Weights W = lbc.weightsAt(P);
  for (std::size_t k = 0; k < inside.size(); ++k)
    if (W.row(Index(k)).sum() > 0.5) s.W0.row(inside[k]) = W.row(Index(k));  // (a point the mesh misses by round-off keeps its heat target)
}

}  // namespace

ExteriorContinuation continuationFor(const Session& s) {
  if (!s.params.kc.guardLobes || s.params.kc.linearEdges) return {};
  // The two-sided blend where the sizing refined a gap between two parts: its width limit is the
  // one the bind's sizing used.
  ExteriorContinuationOptions o;
  o.blendWidth = bindSizingOptions(s.params).outsideNarrowWidth;
  return ExteriorContinuation(s.samples, s.cage, s.params.spacing, s.sizing.get(), o);
}

std::vector<Index> rederivedRows(const Session& s, std::span<const Index> rows) { return rederivedRows(s, continuationFor(s), rows); }

std::vector<Index> rederivedRows(const Session& s, const ExteriorContinuation& continuation, std::span<const Index> rowsIn) {
  std::vector<Index> rows(rowsIn.begin(), rowsIn.end());
  if (!continuation.rows().empty()) {
    std::vector<char> touched(static_cast<std::size_t>(s.samples.size()), 0);
    for (Index i : rowsIn) touched[static_cast<std::size_t>(i)] = 1;
    for (std::size_t k = 0; k < continuation.rows().size(); ++k) {
      bool reads = touched[static_cast<std::size_t>(continuation.rows()[k])] != 0;
      for (Index j : continuation.sources(k)) reads = reads || touched[static_cast<std::size_t>(j)] != 0;
      if (reads) rows.push_back(continuation.rows()[k]);
    }
  }
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

LobeLiftReport liftFieldLobes(const Session& s, KernelField& field) {
  field.clearLift();
  if (s.params.kc.method != Method::QP || !s.params.kc.liftLobes) return {};
  // Not where post-processing sets the field (linear edges, lines through the samples) or with
  // rigid regions, whose weights the rigidity QP makes: the bumps would bend them.
  if (s.hasRigidity() || !s.structure.rigid.empty() || s.params.kc.linearEdges ||
      (!s.structure.lines.empty() && !s.params.kc.exactLines))
    return {};
  return liftLobes(field, s.cage, s.samples.kind);
}

void installLobeBound(const Session& s, CoordinateField& field) {
  const KcParams& kc = s.params.kc;
  const bool bounded = kc.lobeBound > 0.0 && kc.method == Method::QP && kc.interp == InterpMode::Exact && !kc.linearEdges &&
                       s.structure.lines.empty() && hasInterior(s.cage);
  field.setLobeBound(bounded ? std::make_shared<LobeBound>(s.cage, kc.lobeBound, s.sigma, kc.qpAllowance) : nullptr);
}

OptimizeReport optimizeRows(Session& s, Method method, std::span<const Index> rows, const ExteriorContinuation& continuation) {
  const WeightOptimizer optimizer(s.cage.C);
  OptimizeOptions oo;
  oo.method = method;
  oo.allowance = s.params.kc.qpAllowance;
  const OptimizeReport r = optimizer.optimize(s.samples, s.W0, s.W, oo, rows);
  if (rows.empty()) {
    continuation.apply(s.W);
  } else if (!continuation.rows().empty()) {
    std::vector<Index> continued;
    std::set_intersection(rows.begin(), rows.end(), continuation.rows().begin(), continuation.rows().end(), std::back_inserter(continued));
    continuation.apply(s.W, continued);
  }
  return r;
}

namespace {

class KcBackend final : public Backend {
 public:
  std::string_view name() const override { return "kc"; }
  std::string_view displayName() const override { return "KC"; }
  std::string_view description() const override { return "kernel coordinates"; }
  const std::vector<BackendParameter>& parameters() const override { return kcParameters(); }
  void writeParameters(const Session& s, nlohmann::json& params) const override { writeKcParameters(s, params); }
  void readParameters(const nlohmann::json& params, Session& s, const std::string& where) const override {
    readKcParameters(params, s, where);
  }
  /// With LBC targets (`--init lbc`) the LBC solver's parameters shape the bind too.
  const Backend* targetsBackend(const BindParams& params) const override {
    return params.kc.init.method == InitMethod::Lbc ? &backendFor("lbc") : nullptr;
  }
  /// With LBC targets the weights' detail is the LBC mesh's, coarser than the samples.
  double weightSpacing(const BindParams& params) const override {
    return params.kc.init.method == InitMethod::Lbc ? params.spacing / kLbcTargetSampling : params.spacing;
  }
  std::string narrowPlaceWarning(const Cage& cage, const BindParams& params) const override {
    return narrowFeatureWarning(cage, params.spacing, params);
  }
  std::string_view tooltip() const override {
    return "Kernel coordinates: smooth influences over the whole picture. You can paint them with the brush, switch the "
           "method (QP / QEC / L1) and move everything outside the cage.";
  }

  BackendCapabilities capabilities() const override {
    BackendCapabilities c;
    c.targets = c.methods = c.painting = c.outsideCage = c.lines = c.rigidity = true;
    return c;
  }

  void bind(Session& s, const BindStep& step) const override {
    const BindParams& params = s.params;
    BindReport& r = s.report;
    const KcParams& kc = params.kc;

    step("sampling", 0.0);
    sampling::SamplingOptions so = samplingOptions(s.imageWidth, s.imageHeight, params);
    so.progress = [&](double f) {
      step("sampling", kStageStart[1] * f);  // throws kc::Cancelled to stop
      return true;
    };
    if (!exactLines(params)) so.lines = s.structure.lines;  // exact lines: the field's correction, not samples
    so.sizing = s.sizing = bindSizing(s.cage, s.structure, params);
    so.gradedLines = gradedSampling(params);
    s.samples = sampling::sample(s.cage, so, &r.sampling);
    // The session records what was sampled: a band that reaches the frame on every side is the frame.
    if (so.exterior == sampling::ExteriorExtent::Band) {
      const sampling::Rect region = sampling::sampledRegion(s.cage, so), frame = sampling::samplingDomain(so);
      if (region.x0 <= frame.x0 && region.y0 <= frame.y0 && region.x1 >= frame.x1 && region.y1 >= frame.y1)
        s.params.exterior = sampling::ExteriorExtent::Frame;
    }

    // K serves the initial weights, then is handed to its factorization, which releases it: the
    // diffusion's factor and K's factor, the two largest allocations of a bind, never coexist.
    step("kernel", kStageStart[1]);
    s.sigma = kc.sigma > 0.0 ? kc.sigma : s.sizing ? sampling::suggestSigma(s.samples.X, *s.sizing) : sampling::suggestSigma(s.samples);
    const GaussianKernel kernel = kernelFor(s.sigma, params.spacing, s.sizing);
    auto t0 = std::chrono::steady_clock::now();
    SparseMatrix K = assembleKernelMatrix(s.samples.X, kernel);
    const double assembleSeconds = secondsSince(t0);

    step("initial weights", kStageStart[2]);
    InitOptions init = kc.init;
    if (init.method == InitMethod::Lbc) init.method = InitMethod::HeatLinear;  // the exterior; the inside follows
    init.locality = locality(s.cage, params, !s.structure.lines.empty() && !kc.exactLines);
    s.W0 = initialWeights(s.samples, s.cage, K, init, &r.init);
    // Screened heat-linear targets lose their faint tail (KcParams::targetFloor).
    if (kc.init.method == InitMethod::HeatLinear && init.locality) floorTargets(s.samples, s.W0, kc.targetFloor);
    if (kc.init.method == InitMethod::Lbc) {
      t0 = std::chrono::steady_clock::now();
      lbcTargetsInside(s, [&](const char*, double f) { step("initial weights", kStageStart[2] + (kStageStart[3] - kStageStart[2]) * f); });
      r.init.seconds += secondsSince(t0);
    }

    step("factorization", kStageStart[3]);
    auto field = std::make_unique<KernelField>();
    r.factor = field->compute(s.samples.X, kernel, kc.interp, std::move(K));
    r.factor.assembleSeconds += assembleSeconds;
    if (r.factor.status != SolveStatus::Ok)
      throw std::invalid_argument("the kernel matrix cannot be factorized (sigma " + std::to_string(s.sigma) + ", spacing " +
                                  std::to_string(params.spacing) + "): " + r.factor.advice);

    step("optimization", kStageStart[4]);
    s.W.resize(s.W0.rows(), s.W0.cols());
    const WeightOptimizer optimizer(s.cage.C);
    OptimizeOptions oo;
    oo.method = kc.method;
    oo.allowance = kc.qpAllowance;
    // In blocks of rows, so progress and Cancel are seen while it runs (rows are independent:
    // the result is the same as one call over all rows).
    const Index n = s.W0.rows(), blocks = std::clamp<Index>(n / 2000, 1, 50);
    std::vector<Index> rows;
    for (Index b = 0; b < blocks; ++b) {
      const Index begin = n * b / blocks, end = n * (b + 1) / blocks;
      rows.resize(static_cast<std::size_t>(end - begin));
      std::iota(rows.begin(), rows.end(), begin);
      const OptimizeReport part = optimizer.optimize(s.samples, s.W0, s.W, oo, rows);
      r.optimize.solved += part.solved;
      r.optimize.infeasible += part.infeasible;
      r.optimize.failed += part.failed;
      r.optimize.maxIterations = std::max(r.optimize.maxIterations, part.maxIterations);
      r.optimize.seconds += part.seconds;
      step("optimization", kStageStart[4] + (kStageStart[5] - kStageStart[4]) * static_cast<double>(end) / static_cast<double>(n));
    }

    step("interpolation", kStageStart[5]);
    const auto ts = std::chrono::steady_clock::now();
    continuationFor(s).apply(s.W);
    field->update(s.W);
    r.lines = applyLines(s, *field);
    s.rigidity = s.structure.rigid.empty() ? std::vector<double>{} : rigidityOfRegions(s.samples.X, s.structure.rigid);
    r.rigidity = applyRigidity(s, *field);
    r.lift = liftFieldLobes(s, *field);
    installLobeBound(s, *field);
    r.timings.solve = secondsSince(ts);
    s.field = std::move(field);
  }

  void rebuildField(Session& s) const override {
    // Coefficients stored with the session (restored by the loader, K not factorized) are kept
    // when they give the stored weights back at the samples; else the field is solved anew.
    if (auto* stored = dynamic_cast<KernelField*>(s.field.get());
        stored && stored->ready() && !stored->factorized() && reproducesWeights(*stored, s)) {
      installLineCorrection(s, *stored);
      installLobeBound(s, *stored);
      return;
    }
    auto field = std::make_unique<KernelField>();
    const InterpolatorReport r = field->compute(s.samples.X, kernelFor(s.sigma, s.params.spacing, s.sizing), s.params.kc.interp);
    if (r.status != SolveStatus::Ok)
      throw std::invalid_argument("the kernel matrix of these samples cannot be factorized: " + r.advice);
    field->update(s.W);
    installLineCorrection(s, *field);
    liftFieldLobes(s, *field);
    installLobeBound(s, *field);
    s.field = std::move(field);
  }

  OptimizeReport reoptimize(Session& s, Method method, std::span<const Index> subset,
                            std::vector<Index>* changedColumns) const override {
    if (s.W0.rows() != s.samples.size() || s.W0.cols() != s.cage.size())
      throw std::invalid_argument("this session has no target weights (weights.initial) to optimize from");
    const bool whole = subset.empty() || s.W.rows() != s.W0.rows() || s.W.cols() != s.W0.cols();
    auto* kernel = dynamic_cast<KernelField*>(s.field.get());
    const bool rigid = s.hasRigidity();
    std::vector<Index> rows(subset.begin(), subset.end());
    if (rigid && !whole && kernel) {  // the rigid zone's rows get their unconstrained weights back first
      const std::vector<Index> zone = rigidityZone(*kernel, s.rigidity);
      rows.insert(rows.end(), zone.begin(), zone.end());
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    }
    if (s.W.rows() != s.W0.rows() || s.W.cols() != s.W0.cols()) s.W = s.W0;
    const Index m = s.W0.cols();
    // With lines, the samples near them are re-derived from W0 too, so that the lines' blend and
    // post-processing start again from the optimizer's weights (as at the bind), not from their
    // own earlier result.
    if (!whole && !s.structure.lines.empty() && !s.params.kc.exactLines) {
      const std::vector<Index> near = lineNeighbourhoodRows(s.cage, s.structure.lines, s.samples.X, s.sigma);
      rows.insert(rows.end(), near.begin(), near.end());
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    }
    // The continued exterior rows (guardLobes) that read a re-optimized row, or are one, are
    // re-derived with them; the columns that change are found over all of those rows.
    const ExteriorContinuation continuation = continuationFor(s);  // built once for both uses
    if (!whole) rows = rederivedRows(s, continuation, rows);
    RowMatrix before(static_cast<Index>(rows.size()), m);
    if (!whole)
      for (std::size_t k = 0; k < rows.size(); ++k) before.row(static_cast<Index>(k)) = s.W.row(rows[k]);
    const OptimizeReport r = optimizeRows(s, method, whole ? std::span<const Index>{} : std::span<const Index>(rows), continuation);
    s.params.kc.method = method;
    if (whole) s.report.optimize = r;

    std::vector<Index> columns;
    for (Index c = 0; c < m; ++c) {
      bool changed = whole;
      for (std::size_t k = 0; k < rows.size() && !whole && !changed; ++k) changed = s.W(rows[k], c) != before(static_cast<Index>(k), c);
      if (changed) columns.push_back(c);
    }
    const bool sampledLines = !s.structure.lines.empty() && !s.params.kc.exactLines;  // the correction follows new weights itself
    if (sampledLines || s.params.kc.linearEdges || rigid) {  // lines and edges made linear again, then rigidity
      if (!kernel) throw std::invalid_argument("this session's field cannot keep its lines and edges linear or its regions rigid");
      kernel->update(s.W);  // applyLines blends from the field of the weights before the lines
      if (!s.structure.lines.empty() || s.params.kc.linearEdges) applyLines(s, *kernel);
      applyRigidity(s, *kernel);
      if (whole) s.report.lift = liftFieldLobes(s, *kernel);
      columns.resize(std::size_t(m));
      std::iota(columns.begin(), columns.end(), Index(0));
    } else if (s.field) {
      if (whole) {
        s.field->update(s.W);
        if (kernel) s.report.lift = liftFieldLobes(s, *kernel);
      } else if (!columns.empty()) s.field->update(s.W, columns);
    }
    if (whole && s.field) installLobeBound(s, *s.field);  // a method switch sets or removes it
    if (changedColumns) *changedColumns = std::move(columns);
    return r;
  }
};

}  // namespace

const Backend& kcBackend() {
  static const KcBackend kc;
  return kc;
}

std::string unsupportedStructure(const Structure& structure, const BackendCapabilities& caps, bool paintedRigidity) {
  const bool lines = !structure.lines.empty() && !caps.lines;
  const bool rigid = (!structure.rigid.empty() || paintedRigidity) && !caps.rigidity;
  return lines && rigid ? "lines and rigid regions" : lines ? "lines" : rigid ? "rigid regions" : "";
}

Structure keptStructure(Structure structure, const BackendCapabilities& caps) {
  if (!caps.lines) structure.lines.clear(), structure.groups.clear();
  if (!caps.rigidity) structure.rigid.clear();
  return structure;
}

std::string structureRefusal(const Structure& structure, const Backend& backend) {
  const std::string missing = unsupportedStructure(structure, backend.capabilities());
  return missing.empty() ? missing : missing + " are not supported by the '" + std::string(backend.name()) + "' backend (use --backend kc)";
}

BackendCapabilities sessionCapabilities(const Session& s) {
  BackendCapabilities c = backendFor(s.params.backend).capabilities();
  if (s.W0.rows() == 0 && c.targets) {
    c.targets = c.methods = c.painting = false;
    c.why = "this session has no target weights (weights.initial), so it cannot be re-optimized or painted";
  }
  if (s.params.exterior == sampling::ExteriorExtent::Band && c.outsideCage) {
    c.outsideCage = false;
    c.why += std::string(c.why.empty() ? "" : "; ") +
             "its weights reach only a band around the cage; bind again with the whole picture sampled "
             "(kcwarp-cli bind --exterior frame; the GUI's Move everything does it)";
  }
  if (s.field && s.field->domain() != FieldDomain::Plane && c.outsideCage) {
    c.outsideCage = false;
    c.why += std::string(c.why.empty() ? "" : "; ") + "this session's field has no weights outside its mesh";
  }
  return c;
}

}  // namespace kc::app
