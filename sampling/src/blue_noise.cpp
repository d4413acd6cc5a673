#include "kc/sampling/blue_noise.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include "kc/core/cage_edge_grid.h"

namespace kc::sampling {
namespace {

/// Uniform double in [0, 1) from 53 random bits (portable, unlike std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/// One jittered point per cell of side c over rect; rows in cell order. Both coordinates are
/// drawn for every cell so the stream does not depend on which points are kept.
std::vector<Vec2> jitteredCells(const Rect& rect, double c, std::mt19937_64& rng) {
  const Index nx = std::max<Index>(1, static_cast<Index>(std::ceil(rect.width() / c)));
  const Index ny = std::max<Index>(1, static_cast<Index>(std::ceil(rect.height() / c)));
  // Stretch the cells slightly so they tile the rectangle exactly.
  const double cx = rect.width() / static_cast<double>(nx), cy = rect.height() / static_cast<double>(ny);
  std::vector<Vec2> pts;
  pts.reserve(static_cast<std::size_t>(nx * ny));
  for (Index j = 0; j < ny; ++j)
    for (Index i = 0; i < nx; ++i) {
      const double u = uniform01(rng), v = uniform01(rng);
      pts.emplace_back(rect.x0 + (static_cast<double>(i) + u) * cx, rect.y0 + (static_cast<double>(j) + v) * cy);
    }
  return pts;
}

Points toPoints(const std::vector<Vec2>& v) {
  Points P(static_cast<Index>(v.size()), 2);
  for (std::size_t k = 0; k < v.size(); ++k) P.row(static_cast<Index>(k)) = v[k].transpose();
  return P;
}

}  // namespace

double blueNoiseCountEstimate(const Rect& domain, double h, double cellArea) {
  const double perimeter = 2.0 * (domain.width() + domain.height());
  return domain.area() / (cellArea * h * h) + perimeter / h + 4.0;
}

Points jitteredStart(const Cage& cage, const Rect& domain, double h, double cellArea, std::uint64_t seed,
                     Index& interiorCount, const Cage* obstacles) {
  std::mt19937_64 rng(seed);
  const double c = h * std::sqrt(cellArea);
  const auto candidates = jitteredCells(domain, c, rng);
  const CageEdgeGrid locator(obstacles ? *obstacles : cage, h);
  const double minDistance = 0.5 * h;
  const CageQueries queries(cage);
  std::vector<Vec2> inside, outside;
  for (const Vec2& p : candidates) {
    if (domain.insideDistance(p) < minDistance) continue;
    if (locator.distance(p, minDistance) < minDistance) continue;
    (queries.inside(p) ? inside : outside).push_back(p);
  }
  interiorCount = static_cast<Index>(inside.size());
  inside.insert(inside.end(), outside.begin(), outside.end());
  return toPoints(inside);
}

BlueNoiseResult blueNoiseSample(const Cage& cage, const Rect& domain, double h, std::uint64_t seed,
                                const BlueNoiseOptions& options, std::span<const StructureLine> lines) {
  BlueNoiseResult result;
  SampleSet& S = result.samples;
  S = boundarySamples(cage, h);
  appendLineSamples(S, lines, h);
  const Cage obstacles = obstacleEdges(cage, lines);
  const Points frame = dropNearCage(cage, framePoints(domain, h), 0.5 * h);
  appendSamples(S, frame, SampleKind::Exterior);
  result.frameCount = frame.rows();
  const Index firstFree = S.size();

  const Points start = jitteredStart(cage, domain, h, options.cellArea, seed, result.interiorCount, &obstacles);
  result.exteriorCount = start.rows() - result.interiorCount;
  appendSamples(S, start.topRows(result.interiorCount), SampleKind::Interior);
  appendSamples(S, start.bottomRows(result.exteriorCount), SampleKind::Exterior);

  InverseMeanShiftOptions relax = options.relax;
  relax.spacing = h;
  RelaxRegion region;
  region.cage = &obstacles;
  region.domain = domain;
  result.relax = relaxInverseMeanShift(S.X, firstFree, region, relax);
  return result;
}

Points blueNoiseRectangle(Index count, const Rect& rect, std::uint64_t seed, InverseMeanShiftOptions relax,
                          InverseMeanShiftReport* report) {
  if (count <= 0) throw std::invalid_argument("blue noise rectangle: count must be positive");
  if (!(rect.width() > 0.0 && rect.height() > 0.0) || !std::isfinite(rect.area()))
    throw std::invalid_argument("blue noise rectangle: the rectangle must have positive, finite size");
  const double h = std::sqrt(rect.area() / (static_cast<double>(count) * kHexCellFactor));
  std::mt19937_64 rng(seed);
  // Cells of area area/count (whole rows and columns, so at least count), then drop random extras.
  const double c = std::sqrt(rect.area() / static_cast<double>(count));
  std::vector<Vec2> pts = jitteredCells(rect, c, rng);  // ceil(W/c)·ceil(H/c) ≥ count cells
  for (Index k = static_cast<Index>(pts.size()); k > count; --k) {
    const auto victim = static_cast<std::size_t>(rng() % static_cast<std::uint64_t>(k));
    pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(victim));
  }
  Points X = toPoints(pts);
  relax.spacing = h;
  RelaxRegion region;
  region.domain = rect;
  region.periodic = true;
  const InverseMeanShiftReport r = relaxInverseMeanShift(X, 0, region, relax);
  if (report) *report = r;
  return X;
}

}  // namespace kc::sampling
