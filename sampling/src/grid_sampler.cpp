#include "kc/sampling/grid_sampler.h"

#include <cmath>

#include "kc/core/cage_edge_grid.h"

namespace kc::sampling {
namespace {
struct GridRange {
  double i0, i1, j0, j1;
};
GridRange gridRange(const Rect& domain, double h) {
  return {std::ceil(domain.x0 / h), std::floor(domain.x1 / h), std::ceil(domain.y0 / h), std::floor(domain.y1 / h)};
}
}  // namespace

double gridPointCount(const Rect& domain, double h) {
  const GridRange g = gridRange(domain, h);
  return std::max(0.0, g.i1 - g.i0 + 1.0) * std::max(0.0, g.j1 - g.j0 + 1.0);
}

SampleSet gridSample(const Cage& cage, const Rect& domain, double h, std::span<const StructureLine> lines) {
  SampleSet S = boundarySamples(cage, h);
  appendLineSamples(S, lines, h);
  const GridRange g = gridRange(domain, h);
  const CageEdgeGrid locator(obstacleEdges(cage, lines), h);
  const double minDistance = 0.5 * h;
  const CageQueries queries(cage);
  std::vector<Vec2> inside, outside;
  for (double j = g.j0; j <= g.j1; j += 1.0) {
    for (double i = g.i0; i <= g.i1; i += 1.0) {
      const Vec2 p(i * h, j * h);
      if (locator.distance(p, minDistance) < minDistance) continue;
      (queries.inside(p) ? inside : outside).push_back(p);
    }
  }
  auto toPoints = [](const std::vector<Vec2>& v) {
    Points P(static_cast<Index>(v.size()), 2);
    for (std::size_t k = 0; k < v.size(); ++k) P.row(static_cast<Index>(k)) = v[k].transpose();
    return P;
  };
  appendSamples(S, toPoints(inside), SampleKind::Interior);
  appendSamples(S, toPoints(outside), SampleKind::Exterior);
  return S;
}

}  // namespace kc::sampling
