#include "kc/app/pipeline.h"
#include "backends.h"
#include "corner_sizing.h"
#include "kc/app/text.h"
#include "kc/app/errors.h"
#include "kc/core/field/kernel_field.h"
#include "kc/core/kernel/gaussian_kernel.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/warp_mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>

namespace kc::app {
namespace {

void checkLocality(const Locality& l) {
  if ((l.rule == Locality::Rule::Spacings || l.rule == Locality::Rule::Pixels) && !(std::isfinite(l.value) && l.value > 0.0))
    throw std::invalid_argument(l.rule == Locality::Rule::Spacings ? "locality spacings must be a positive number"
                                                                   : "locality must be a positive number of pixels");
}

void checkCommonParams(int width, int height, const BindParams& p) {
  checkImageSize(width, height, "bind", "image");
  if (!(p.spacing >= kMinSpacing) || !std::isfinite(p.spacing))
    throw std::invalid_argument("spacing must be a number of pixels ≥ " + std::to_string(kMinSpacing).substr(0, 4));
  if (!std::isfinite(p.kc.sigma) || p.kc.sigma < 0.0) throw std::invalid_argument("sigma must be positive (or 0 for automatic)");
  if (p.kc.init.iterations < 0 || p.kc.init.iterations > kMaxHeatIterations)
    throw std::invalid_argument("heat iterations must be in 0.." + std::to_string(kMaxHeatIterations) + " (0 = steady state)");
  checkLocality(p.kc.locality);
  if (!(p.kc.targetFloor >= 0.0 && p.kc.targetFloor < kMaxTargetFloor))
    throw std::invalid_argument("the target floor must be in [0, 0.5) (0 = off)");
  if (!std::isfinite(p.margin) || p.margin > kMaxCoordinate) throw std::invalid_argument("margin must be a finite number of pixels");
}

/// True when every cage edge is at least `length` long (O(m)). A cage with a shorter edge is
/// refused by checkCageScale at that spacing; looking for its narrow places within a few spacings
/// would only cost time (a 40,000-point circle has ~10^7 edge pairs within 2h).
bool edgesAtLeast(const Cage& cage, double length) {
  for (const auto& [a, b] : cageEdges(cage))
    if ((cage.C.row(a) - cage.C.row(b)).norm() < length) return false;
  return true;
}

/// The narrow place g of the cage in words: "cage points A and B are D px apart" or "cage edges
/// a-b and c-d come within D px of each other".
std::string describeGap(const Cage& cage, const CageGap& g) {
  if (g.pointA >= 0)
    return "cage points " + std::to_string(g.pointA) + " and " + std::to_string(g.pointB) + " are " + shortNumber(g.distance) +
           " px apart";
  const auto edges = cageEdges(cage);
  const auto e = edges[std::size_t(g.edgeA)], f = edges[std::size_t(g.edgeB)];
  return "cage edges " + std::to_string(e[0]) + "-" + std::to_string(e[1]) + " and " + std::to_string(f[0]) + "-" +
         std::to_string(f[1]) + " come within " + shortNumber(g.distance) + " px of each other";
}

/// Refuses a cage with a feature narrower than the sampling can resolve: an edge shorter than
/// kMinFeatureSpacings·h, or two edges sharing no end point closer than that (a thin sliver, the
/// turns of a tight spiral). Such cages bind with wrong weights (see kMinFeatureSpacings).
void checkCageScale(const Cage& cage, double spacing, bool graded = false) {
  const double below = kMinFeatureSpacings * spacing;
  const CageGap g = narrowestGap(cage, below);
  if (!std::isfinite(g.distance)) return;
  if (graded)
    throw std::invalid_argument(describeGap(cage, g) + ", narrower than the " + shortNumber(below) +
                                " px kcwarp resolves: " + (g.pointA >= 0 ? "merge them" : "widen the gap"));
  throw std::invalid_argument(describeGap(cage, g) + ", less than the spacing " + shortNumber(below) + " px: " +
                              (g.pointA >= 0 ? "merge them" : "widen the gap") + ", or use --spacing " +
                              shortNumber(g.distance / kMinFeatureSpacings) + " or less");
}


/// k and n of the LBC backend's mesh (SizingOptions::featureSamples, extraFeatureSamples,
/// narrowWidth and extraNarrowWidth): one triangle across a narrow part of the inside, where the weights follow
/// the cage edges' linear data. The mesh covers the inside
/// only, so a gap outside the cage (between two legs) does not refine it (SizingOptions::outsideGaps).
constexpr double kLbcFeatureSamples = 1.0;
/// g of the LBC backend's mesh (SizingOptions::gradation): the steepest grading the sizing field
/// allows. The Delaunay mesher keeps its angle bound at any grading, and the ADMM solve's cost
/// follows the vertex count, which a steeper grading keeps near the uniform mesh's.
constexpr double kLbcGradation = 0.5;

/// True when a bind with `p` samples or meshes with a sizing field: graded, and blue noise for a
/// backend that samples the picture (kc); the LBC mesh of the cage interior.
bool gradedBind(const BindParams& p) {
  if (!backendFor(p.backend).capabilities().outsideCage) return p.graded;
  return p.graded && p.sampler == sampling::SamplerKind::BlueNoise;
}

/// Where the kernel's width may vary freely: exact interpolation (the thesis's plain form loses
/// partition of unity where it varies) without linearEdges' post-processing of the edges' rows.
bool exactVaryingWidth(const BindParams& p) { return p.kc.interp == InterpMode::Exact && !p.kc.linearEdges; }

}  // namespace

bool gradedSampling(const BindParams& params) { return gradedBind(params); }

bool exactLines(const BindParams& params) {
  return params.kc.exactLines && backendFor(params.backend).capabilities().outsideCage;
}

SizingOptions bindSizingOptions(const BindParams& params) {
  SizingOptions o;
  o.hMax = params.spacing;
  o.hMin = std::min(kMinSpacing, params.spacing);
  if (!backendFor(params.backend).capabilities().outsideCage) {
    o.featureSamples = o.extraFeatureSamples = o.narrowWidth = o.extraNarrowWidth = kLbcFeatureSamples;
    o.gradation = o.fineGradation = kLbcGradation;
    o.outsideGaps = false;
  }
  // A gap between two parts gets kOutsideFeatureSamples where the interpolation is exact and the
  // edges are not post-processed, as sharp corners (bindSizing); otherwise the cage's k below n·hMax.
  if (!exactVaryingWidth(params)) {
    o.outsideFeatureSamples = o.featureSamples;
    o.outsideNarrowWidth = o.narrowWidth;
  }
  return o;
}

std::shared_ptr<const SizingField> bindSizing(const Cage& cage, const Structure& structure, const BindParams& params) {
  if (!gradedBind(params)) return nullptr;
  std::vector<FeatureSegment> extra;
  const bool sampledLines = !structure.lines.empty() && !exactLines(params);
  if (sampledLines)
    for (const StructureLine& l : structure.lines) extra.push_back({l.a, l.b});
  for (const RigidRegion& r : structure.rigid)
    for (Index i = 0; i < r.polygon.rows(); ++i) extra.push_back({r.polygon.row(i), r.polygon.row((i + 1) % r.polygon.rows())});
  const SizingOptions o = bindSizingOptions(params);
  SizingField h = featureSizing(cage, extra, o);
  // Sharp outside corners sampled finer (guardLobes) where the interpolation is exact (the thesis's
  // plain form loses partition of unity where the kernel's width varies: 0.09 on the figure) and
  // the edges are not post-processed (linearEdges, which the finer corners left 1.8e-3 from linear
  // on the figure instead of 3.1e-4).
  if (params.kc.guardLobes && exactVaryingWidth(params) &&
      backendFor(params.backend).capabilities().outsideCage)
    h = withSharpCorners(cage, o, h);
  if (!h.graded()) return nullptr;
  // The kernel width follows the smooth profile where structure lines need it (a width with kinks
  // bends them: 0.55 px on random lines in the star, 0.03 px smooth); elsewhere the spacing itself,
  // which keeps the weights more local (person legs 4 px apart: 0.018 across the gap, 0.034 smooth).
  const SizingForm form = sampledLines ? SizingForm::Smooth : SizingForm::Min;
  return std::make_shared<SizingField>(h.hMax(), h.gradation(), h.seeds(), h.sizes(), form, h.slopes());
}

BindParams effectiveBindParams(const Cage& cage, const Structure& structure, const BindParams& params) {
  BindParams p = params;
  if (structure.lines.empty() || !gradedBind(p) || !backendFor(p.backend).capabilities().outsideCage || exactLines(p)) return p;
  try {
    checkCageScale(cage, p.spacing);
    validateLines(cage, structure.lines, p.spacing, false);
    p.graded = false;
  } catch (const std::exception&) {  // refused uniformly: graded (bad lines are refused by the bind)
  }
  return p;
}

double localityLength(const Cage& cage, double spacing, double spacings) {
  const double base = spacings * spacing;
  if (!cage.closed || cage.size() < 3) return base;
  const Vec2 lo = cage.C.colwise().minCoeff().transpose(), hi = cage.C.colwise().maxCoeff().transpose();
  const Vec2 size = hi - lo;
  const double step = std::max(0.5 * spacing, std::sqrt(size.x() * size.y() / 20000.0));
  if (!(step > 0.0) || !std::isfinite(step)) return base;
  const CageQueries queries(cage);
  double depth = 0.0;
  for (double y = lo.y() + 0.5 * step; y < hi.y(); y += step)
    for (double x = lo.x() + 0.5 * step; x < hi.x(); x += step)
      if (const Vec2 p(x, y); queries.inside(p)) depth = std::max(depth, queries.distance(p));
  return std::max(base, depth / 4.0);
}

std::optional<double> locality(const Cage& cage, const BindParams& params, bool sampledLines) {
  const Locality& l = params.kc.locality;
  checkLocality(l);
  switch (l.rule) {
    case Locality::Rule::Off:
      return std::nullopt;
    case Locality::Rule::Spacings:
      if (sampledLines) return std::nullopt;  // their linear fit bends where the targets fall off steeply
      return localityLength(cage, params.spacing, l.value);
    case Locality::Rule::Pixels:
      return l.value;
    case Locality::Rule::Automatic:
      return automaticLocality(cage.C);
  }
  return std::nullopt;
}

double automaticSigma(double spacing) { return 3.0 * spacing / std::numbers::pi; }

sampling::SamplingOptions samplingOptions(int width, int height, const BindParams& p) {
  sampling::SamplingOptions so;
  so.spacing = p.spacing;
  so.width = width;
  so.height = height;
  // The plain (thesis) interpolation is accurate only a few kernel widths inside the sampled
  // domain (thesis Fig 3.1), so it gets a wider automatic margin than the exact one.
  so.margin = p.margin >= 0.0 || p.kc.interp == InterpMode::Exact ? p.margin : kThesisMarginSpacings * p.spacing;
  so.kind = p.sampler;
  so.seed = p.seed;
  so.exterior = p.exterior;
  // The band reaches past the outer vertices of the warp-mesh triangles that meet the cage (fixed
  // and transparent evaluate the field there; they lie within one mesh cell, √2·s, of the cage):
  // two automatic mesh cells, when that is wider than kExteriorBandSpacings·h (a small cage on a
  // very large picture, whose mesh spacing follows the picture).
  if (p.exterior == sampling::ExteriorExtent::Band)
    so.band = std::max(sampling::kExteriorBandSpacings * p.spacing, 2.0 * automaticMeshSpacing(width, height, weightSpacing(p)));
  return so;
}

namespace {

/// estimateBindCost for parameters that are already the bind's own (effectiveBindParams).
BindCost costOf(const Cage& cage, const Structure& structure, int width, int height, const BindParams& params) {
  if (gradedBind(params) && backendFor(params.backend).capabilities().outsideCage) {
    // A graded sampling only adds samples to the uniform one: past the limits already, it is not
    // worth finding its sizing field (O(edges · neighbours), slow on a cage of 40,000 points).
    BindParams uniform = params;
    uniform.graded = false;
    const BindCost c = costOf(cage, structure, width, height, uniform);
    if (bindLimitFactor(c) > 1.0) return c;
  }
  sampling::SamplingOptions so = samplingOptions(width, height, params);
  so.sizing = bindSizing(cage, structure, params);
  BindCost c;
  c.samples = sampling::estimateSampleCount(cage, so);
  c.controls = static_cast<double>(cage.size());
  const sampling::Rect d = sampling::sampledRegion(cage, so);
  const double area = std::max(d.area(), 1.0);
  const double cutoff = GaussianKernel::forSpacing(params.kc.sigma > 0.0 ? params.kc.sigma : automaticSigma(params.spacing), params.spacing).cutoff();
  const double neighbours = std::min(c.samples, 1.0 + c.samples * std::numbers::pi * cutoff * cutoff / area);
  c.kernelNonZeros = c.samples * neighbours;
  c.bytes = kDenseBytesPerWeight * c.samples * c.controls + kBytesPerKernelNonZero * c.kernelNonZeros;
  return c;
}

}  // namespace

BindCost estimateBindCost(const Cage& cage, int width, int height, const BindParams& params) {
  return costOf(cage, Structure{}, width, height, params);
}

BindCost estimateBindCost(const Cage& cage, const Structure& structure, int width, int height, const BindParams& params) {
  return costOf(cage, structure, width, height, effectiveBindParams(cage, structure, params));
}

sampling::ExteriorExtent exteriorFor(OutsideMode outside) {
  return outside == OutsideMode::Deform ? sampling::ExteriorExtent::Frame : sampling::ExteriorExtent::Band;
}

double weightSpacing(const BindParams& params) { return backendFor(params.backend).weightSpacing(params); }

double automaticSpacing(const Cage& cage, int width, int height, const BindParams& params, double budget) {
  if (!backendFor(params.backend).capabilities().outsideCage) {  // the LBC mesh of the cage interior
    double h = params.spacing;
    for (int step = 0; step < 3 && estimateMeshVertices(cage, h) > kAutoLbcVertices; ++step)
      h *= std::sqrt(estimateMeshVertices(cage, h) / kAutoLbcVertices);
    return std::max(params.spacing, std::ceil(h * 100.0) / 100.0);
  }
  // A feature narrower than a graded sampling resolves is refused by bind(): no spacing to find.
  if (gradedBind(params) && std::isfinite(narrowestGap(cage, kNarrowWidth * kMinSpacing).distance)) return params.spacing;
  if (params.kc.init.method == InitMethod::Lbc) {  // the LBC mesh at a plain bind's spacing, samples denser
    BindParams plain = params;
    plain.kc.init.method = InitMethod::HeatLinear;
    BindParams p = params;
    for (p.spacing = automaticSpacing(cage, width, height, plain, budget) * kLbcTargetSampling;
         bindLimitFactor(estimateBindCost(cage, width, height, p)) > 1.0 && p.spacing < 1e6; p.spacing *= 1.05) {
    }
    return std::ceil(p.spacing * 100.0) / 100.0;
  }
  // The budget is counted over the cage and a band around it whatever the extent sampled, so the
  // spacing follows the cage: the same cage 10× larger gets 10× the spacing and the same count.
  // The budget is that of the uniform sampling: a graded one adds what its narrow places need.
  BindParams p = params;
  p.exterior = sampling::ExteriorExtent::Band;
  p.graded = false;
  double h = params.spacing;
  if (estimateBindCost(cage, width, height, p).samples > budget) {
    for (int step = 0; step < 3; ++step) p.spacing *= std::sqrt(estimateBindCost(cage, width, height, p).samples / budget);
    h = std::max(params.spacing, std::ceil(p.spacing * 100.0) / 100.0);
  }
  p = params;
  // A whole-frame bind at that spacing may still pass kcwarp's limits on a big picture: h grows
  // by 5% until it fits.
  // (At most 100 steps, 130×: a graded sampling's refinement shrinks little as h grows.)
  int steps = 0;
  for (p.spacing = h; bindLimitFactor(estimateBindCost(cage, width, height, p)) > 1.0 && p.spacing < 1e6 && steps < 100;
       p.spacing *= 1.05, ++steps) {
  }
  h = std::ceil(p.spacing * 100.0) / 100.0;
  if (h == params.spacing || gradedBind(params)) return h;  // a graded sampling resolves its narrow places itself
  // A narrow place of the cage keeps about kNarrowFeatureSpacings samples across it, over the
  // budget if need be, but not past the limits: h grows from there by 5% until the bind fits.
  if (!edgesAtLeast(cage, kMinFeatureSpacings * params.spacing)) return h;  // bind() refuses it anyway
  const CageGap g = narrowestGap(cage, kNarrowFeatureSpacings * h);
  if (!std::isfinite(g.distance)) return h;
  for (double narrow = std::max(params.spacing, std::floor(g.distance / kNarrowFeatureSpacings * 100.0) / 100.0); narrow < h;
       narrow *= 1.05) {
    p.spacing = narrow;
    if (bindLimitFactor(estimateBindCost(cage, width, height, p)) <= 1.0) return narrow;
  }
  return h;
}

std::string narrowFeatureWarning(const Cage& cage, double spacing, const BindParams& params) {
  if (gradedBind(params)) return "";
  return narrowFeatureWarning(cage, spacing);
}

std::string narrowFeatureWarning(const Cage& cage, double spacing) {
  // Narrower than kMinFeatureSpacings·h is refused by the bind itself (checkCageScale).
  if (!edgesAtLeast(cage, kMinFeatureSpacings * spacing)) return "";
  const CageGap g = narrowestGap(cage, kNarrowFeatureSpacings * spacing);
  if (!std::isfinite(g.distance) || g.distance < kMinFeatureSpacings * spacing) return "";
  return describeGap(cage, g) + ", less than twice the spacing " + shortNumber(spacing) +
         " px: the weights there are coarse (spacing " + shortNumber(g.distance / kNarrowFeatureSpacings) +
         " px or less resolves them)";
}

double bindLimitFactor(const BindCost& c) {
  // Samples and non-zeros grow like 1/h², the dense weights like m/h².
  return std::max({c.samples / double(kMaxBindSamples), c.kernelNonZeros / double(kMaxKernelNonZeros), c.bytes / double(kMaxBindBytes)});
}

void checkBindCost(const BindCost& c, const BindParams& params) {
  const std::string needs = "this bind would need about " + shortNumber(c.samples) + " samples, " + shortNumber(c.kernelNonZeros) +
                            " kernel non-zeros and " + byteText(c.bytes) + " of memory";
  const double factor = bindLimitFactor(c);
  if (factor <= 1.0) return;
  const double sigmaShare = params.kc.sigma > 0.0 ? c.kernelNonZeros / std::max(c.samples, 1.0) : 0.0;
  std::string advice = "use --spacing " + shortNumber(params.spacing * std::sqrt(factor) * 1.05) + " or more";
  if (params.kc.sigma > 0.0 && c.samples <= double(kMaxBindSamples) && sigmaShare > 1000.0)
    advice = "sigma " + shortNumber(params.kc.sigma) + " px is very wide for spacing " + shortNumber(params.spacing) +
             " px (each sample would touch " + shortNumber(sigmaShare) + " others): use --sigma 0 (automatic, about " +
             shortNumber(automaticSigma(params.spacing)) + " px) or a larger --spacing";
  if (kDenseBytesPerWeight * c.samples * c.controls > double(kMaxBindBytes))
    advice += ", or a cage with fewer points (" + shortNumber(c.controls) + " now; the weights alone take " +
              byteText(kDenseBytesPerWeight * c.samples * c.controls) + ")";
  throw std::invalid_argument(needs + ", above kcwarp's limits (" + shortNumber(double(kMaxBindSamples)) + " samples, " +
                              shortNumber(double(kMaxKernelNonZeros)) + " non-zeros, " + byteText(double(kMaxBindBytes)) + "): " + advice);
}

Session bind(const Cage& cage, int width, int height, const BindParams& params, const StageProgress& progress) {
  return app::bind(cage, Structure{}, width, height, params, progress);
}

Session bind(const Cage& cage, const Structure& structure, int width, int height, const BindParams& requested,
             const StageProgress& progress) {
  // Structure lines keep the uniform sampling where its rules accept the cage and the lines.
  const BindParams params = asUserInput("bind", [&] { return effectiveBindParams(cage, structure, requested); });
  const auto t0 = std::chrono::steady_clock::now();
  // What the user gave (cage, parameters, image size): a lower layer's rejection is bad input.
  const Backend& backend = asUserInput("bind", [&]() -> const Backend& {
    validateCage(cage);
    checkCommonParams(width, height, params);
    const Backend& b = backendFor(params.backend);
    // A graded sampling refines its narrow places down to kMinSpacing: narrower than
    // kNarrowWidth·kMinSpacing is degenerate (points to merge, a gap to widen).
    if (!gradedBind(params)) checkCageScale(cage, params.spacing);
    else checkCageScale(cage, kNarrowWidth * kMinSpacing, true);
    if (b.capabilities().outsideCage)  // the sample-cost estimate is for backends that sample the whole image
      checkBindCost(costOf(cage, structure, width, height, params), params);
    if (const std::string refusal = structureRefusal(structure, b); !refusal.empty()) throw std::invalid_argument(refusal);
    validateLines(cage, structure.lines, params.spacing, gradedBind(params) || exactLines(params));
    if (params.kc.linearEdges && loopEdges(cage).size() != cageEdges(cage).size())
      throw std::invalid_argument("--linear-edges needs a cage without sticks (measured on the stick figure: the sticks' "
                                  "linearity went from 0.031 to 0.089 and the head's lobe from -0.05 to -0.83)");
    validateRigidRegions(cage, structure.rigid);
    return b;
  });
  Session s;
  s.cage = cage;
  s.structure = structure;
  s.params = params;
  s.imageWidth = width;
  s.imageHeight = height;
  // The backend throws std::invalid_argument for parameters it rejects (documented in backend.h).
  asUserInput("bind", [&] {
    backend.bind(s, [&](const char* stage, double f) {
      if (progress && !progress(stage, f)) throw Cancelled();
    });
  });
  if (progress && !progress("done", 1.0)) throw Cancelled();
  // The stages' times from their reports; the field's solve (timings.solve) the backend set itself.
  BindReport& r = s.report;
  r.timings.sampling = r.sampling.seconds;
  r.timings.assemble = r.factor.assembleSeconds;
  r.timings.factor = r.factor.factorSeconds;
  r.timings.init = r.init.seconds;
  r.timings.optimize = r.optimize.seconds;
  r.timings.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

OptimizeReport reoptimize(Session& session, Method method, std::span<const Index> subset,
                          std::vector<Index>* changedColumns) {
  const BackendCapabilities caps = sessionCapabilities(session);
  if (!caps.methods) throw std::invalid_argument("this session cannot be re-optimized: " + caps.why);
  return backendFor(session.params.backend).reoptimize(session, method, subset, changedColumns);
}

void refreshField(Session& session) { backendFor(session.params.backend).rebuildField(session); }

void releaseFactorization(Session& session) {
  if (session.field) session.field->releaseWorkspace();
}

}  // namespace kc::app
