#include "kc/sampling/sampler.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "kc/sampling/blue_noise.h"
#include "kc/sampling/grid_sampler.h"

namespace kc::sampling {
namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

void validate(const Cage& cage, const SamplingOptions& o) {
  const double h = o.spacing;
  if (!std::isfinite(h) || !(h > 0.0)) throw std::invalid_argument("sampling: spacing must be a positive number (got " + num(h) + ")");
  if (!std::isfinite(o.width) || !std::isfinite(o.height) || !(o.width > 0.0) || !(o.height > 0.0))
    throw std::invalid_argument("sampling: image size must be positive (got " + num(o.width) + " x " + num(o.height) + ")");
  if (!std::isfinite(o.margin)) throw std::invalid_argument("sampling: margin must be finite");
  if (!std::isfinite(o.band)) throw std::invalid_argument("sampling: band width must be finite");
  validateCage(cage);
  validateLines(cage, o.lines, h, o.gradedLines || (o.sizing && o.sizing->graded()));
  const double extent = std::max(cage.C.col(0).maxCoeff() - cage.C.col(0).minCoeff(), cage.C.col(1).maxCoeff() - cage.C.col(1).minCoeff());
  if (h > extent)
    throw std::invalid_argument("sampling: spacing " + num(h) + " is larger than the cage (" + num(extent) +
                                " pixels across); use a spacing below " + num(extent / 4.0));
  const Rect domain = samplingDomain(o);
  for (Index i = 0; i < cage.size(); ++i)
    if (!domain.contains(cage.C.row(i)))
      throw std::invalid_argument("sampling: cage point " + std::to_string(i) + " (" + num(cage.C(i, 0)) + ", " + num(cage.C(i, 1)) +
                                  ") lies outside the image domain [0, " + num(o.width) + "] x [0, " + num(o.height) +
                                  "] plus its margin of " + num(resolvedMargin(o)) + " pixels");
}

/// Throws when about `count` samples at spacing h exceed kMaxSamples (count ∝ 1/h²).
void checkCount(double count, double h) {
  if (count <= static_cast<double>(kMaxSamples)) return;
  const double fits = h * std::sqrt(count / static_cast<double>(kMaxSamples)) * 1.05;
  throw std::invalid_argument("sampling: spacing " + num(h) + " would give about " + num(std::round(count)) +
                              " samples, more than the limit of " + std::to_string(kMaxSamples) +
                              "; use a spacing of at least " + num(fits));
}

const SizingField* gradedSizing(const SamplingOptions& o) {
  return o.sizing && o.sizing->graded() && o.kind == SamplerKind::BlueNoise ? o.sizing.get() : nullptr;
}

double perimeterSamples(const Cage& cage, const SamplingOptions& o) {
  double n = static_cast<double>(cage.size());
  const SizingField* sizing = gradedSizing(o);
  for (const auto& [a, b] : cageEdges(cage))
    n += sizing ? static_cast<double>(segmentDivision(cage.C.row(a), cage.C.row(b), *sizing).size()) - 1.0
                : static_cast<double>(edgePieces((cage.C.row(a) - cage.C.row(b)).norm(), o.spacing));
  return n;
}

double lineSampleCount(const SamplingOptions& o) {
  double n = 0.0;
  const SizingField* sizing = gradedSizing(o);
  for (const StructureLine& l : o.lines)
    n += static_cast<double>(sizing ? lineSamplePoints(l, *sizing).rows() : lineSamplePoints(l, o.spacing).rows());
  return n;
}

}  // namespace

double resolvedMargin(const SamplingOptions& options) {
  return options.margin >= 0.0 ? options.margin : 3.0 * options.spacing;
}

Rect samplingDomain(const SamplingOptions& options) {
  const double g = resolvedMargin(options);
  return {-g, -g, options.width + g, options.height + g};
}

double resolvedBand(const SamplingOptions& options) {
  return options.band >= 0.0 ? options.band : kExteriorBandSpacings * options.spacing;
}

Rect sampledRegion(const Cage& cage, const SamplingOptions& options) {
  const Rect frame = samplingDomain(options);
  if (options.exterior == ExteriorExtent::Frame || cage.size() == 0) return frame;
  const double b = resolvedBand(options);
  const Rect box{cage.C.col(0).minCoeff() - b, cage.C.col(1).minCoeff() - b, cage.C.col(0).maxCoeff() + b,
                 cage.C.col(1).maxCoeff() + b};
  return {std::max(frame.x0, box.x0), std::max(frame.y0, box.y0), std::min(frame.x1, box.x1), std::min(frame.y1, box.y1)};
}

double estimateSampleCount(const Cage& cage, const SamplingOptions& options) {
  const double h = options.spacing;
  const Rect domain = sampledRegion(cage, options);
  const SizingField* sizing = gradedSizing(options);
  const double free = options.kind == SamplerKind::Grid ? gridPointCount(domain, h)
                      : sizing ? gradedCountEstimate(domain, *sizing, options.blueNoise.cellArea) +
                                     2.0 * (domain.width() + domain.height()) / h + 4.0
                               : blueNoiseCountEstimate(domain, h, options.blueNoise.cellArea);
  return free + perimeterSamples(cage, options) + lineSampleCount(options);
}

SampleSet sample(const Cage& cage, const SamplingOptions& options, SamplingReport* report) {
  const auto start = std::chrono::steady_clock::now();
  validate(cage, options);
  const double h = options.spacing;
  if (options.sizing && options.sizing->graded() && options.kind == SamplerKind::Grid)
    throw std::invalid_argument("sampling: the grid sampler is uniform and this cage has narrow places: use the blue-noise sampler");
  if (options.sizing && options.sizing->hMax() != h)
    throw std::invalid_argument("sampling: the sizing field's largest spacing must be the spacing");
  const Rect domain = sampledRegion(cage, options);
  SamplingReport r;
  SampleSet S;
  if (options.kind == SamplerKind::Grid) {
    checkCount(estimateSampleCount(cage, options), h);
    S = gridSample(cage, domain, h, options.lines);
  } else {
    if (!(options.blueNoise.cellArea > 0.0) || !std::isfinite(options.blueNoise.cellArea))
      throw std::invalid_argument("sampling: blue-noise cell area must be positive");
    checkCount(estimateSampleCount(cage, options), h);
    BlueNoiseOptions bo = options.blueNoise;
    if (options.exterior == ExteriorExtent::Band) bo.cellGrid = samplingDomain(options);
    if (options.progress) bo.relax.progress = options.progress;
    bo.relax.sizing = gradedSizing(options);
    BlueNoiseResult b = blueNoiseSample(cage, domain, h, options.seed, bo, options.lines);
    S = std::move(b.samples);
    r.frame = b.frameCount;
    r.iterations = b.relax.iterations;
    r.converged = b.relax.converged;
    r.lastMove = b.relax.lastMove;
    r.rejectedMoves = b.relax.rejectedMoves;
  }
  for (SampleKind k : S.kind) {
    switch (k) {
      case SampleKind::Control: ++r.controls; break;
      case SampleKind::Edge: ++r.edge; break;
      case SampleKind::Interior: ++r.interior; break;
      case SampleKind::Exterior: ++r.exterior; break;
      case SampleKind::Line: ++r.line; break;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (report) *report = r;
  return S;
}

}  // namespace kc::sampling
