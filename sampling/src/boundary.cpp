#include "kc/sampling/boundary.h"

#include <algorithm>
#include <cmath>

#include "kc/core/cage_edge_grid.h"

namespace kc::sampling {

double Rect::insideDistance(const Vec2& p) const {
  return std::min(std::min(p.x() - x0, x1 - p.x()), std::min(p.y() - y0, y1 - p.y()));
}

Index edgePieces(double length, double h) {
  return std::max<Index>(1, static_cast<Index>(std::llround(length / h)));
}

SampleSet boundarySamples(const Cage& cage, double h) {
  const Index m = cage.size();
  const auto edges = cageEdges(cage);
  Index total = m;
  for (const auto& [a, b] : edges) total += edgePieces((cage.C.row(a) - cage.C.row(b)).norm(), h) - 1;

  SampleSet S;
  S.X.resize(total, 2);
  S.kind.assign(static_cast<std::size_t>(total), SampleKind::Edge);
  S.edge.setConstant(total, 2, -1);
  S.X.topRows(m) = cage.C;
  std::fill(S.kind.begin(), S.kind.begin() + m, SampleKind::Control);
  Index row = m;
  for (const auto& [a, b] : edges) {
    const Vec2 A = cage.C.row(a), B = cage.C.row(b);
    const Index n = edgePieces((B - A).norm(), h);
    for (Index k = 1; k < n; ++k) {
      const double t = static_cast<double>(k) / static_cast<double>(n);
      S.X.row(row) = ((1.0 - t) * A + t * B).transpose();
      S.edge(row, 0) = a;
      S.edge(row, 1) = b;
      ++row;
    }
  }
  return S;
}

Points framePoints(const Rect& domain, double h) {
  // Counter-clockwise sides; the coordinate that is constant along a side is copied exactly so
  // every point lies on the rectangle (no rounding outside it).
  const Index nx = edgePieces(domain.width(), h), ny = edgePieces(domain.height(), h);
  auto lerp = [](double a, double b, Index k, Index n) {
    const double t = static_cast<double>(k) / static_cast<double>(n);
    return std::clamp((1.0 - t) * a + t * b, std::min(a, b), std::max(a, b));
  };
  Points P(2 * (nx + ny), 2);
  Index row = 0;
  for (Index k = 0; k < nx; ++k) P.row(row++) << lerp(domain.x0, domain.x1, k, nx), domain.y0;
  for (Index k = 0; k < ny; ++k) P.row(row++) << domain.x1, lerp(domain.y0, domain.y1, k, ny);
  for (Index k = 0; k < nx; ++k) P.row(row++) << lerp(domain.x1, domain.x0, k, nx), domain.y1;
  for (Index k = 0; k < ny; ++k) P.row(row++) << domain.x0, lerp(domain.y1, domain.y0, k, ny);
  return P;
}

void appendSamples(SampleSet& S, const Points& P, SampleKind kind) {
  const Index n0 = S.X.rows(), n = P.rows();
  S.X.conservativeResize(n0 + n, 2);
  S.X.bottomRows(n) = P;
  S.edge.conservativeResize(n0 + n, 2);
  S.edge.bottomRows(n).setConstant(-1);
  S.kind.insert(S.kind.end(), static_cast<std::size_t>(n), kind);
}

void appendLineSamples(SampleSet& S, std::span<const StructureLine> lines, double h) {
  for (const StructureLine& l : lines) {
    const Index first = S.X.rows();
    appendSamples(S, lineSamplePoints(l, h), SampleKind::Line);
    std::vector<Index> idx(static_cast<std::size_t>(S.X.rows() - first));
    for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = first + static_cast<Index>(k);
    S.lines.push_back(std::move(idx));
  }
}

Cage obstacleEdges(const Cage& cage, std::span<const StructureLine> lines) {
  Cage o;
  o.closed = cage.closed;
  o.edges = cageEdges(cage);
  const Index m = cage.size(), n = static_cast<Index>(lines.size());
  o.C.resize(m + 2 * n, 2);
  o.C.topRows(m) = cage.C;
  for (Index k = 0; k < n; ++k) {
    o.C.row(m + 2 * k) = lines[static_cast<std::size_t>(k)].a.transpose();
    o.C.row(m + 2 * k + 1) = lines[static_cast<std::size_t>(k)].b.transpose();
    o.edges.push_back({static_cast<int>(m + 2 * k), static_cast<int>(m + 2 * k + 1)});
  }
  return o;
}

Points dropNearCage(const Cage& cage, const Points& P, double minDistance) {
  const CageEdgeGrid locator(cage, std::max(minDistance, 1e-9));
  std::vector<Index> keep;
  keep.reserve(static_cast<std::size_t>(P.rows()));
  for (Index i = 0; i < P.rows(); ++i)
    if (locator.distance(P.row(i), minDistance) >= minDistance) keep.push_back(i);
  Points Q(static_cast<Index>(keep.size()), 2);
  for (std::size_t k = 0; k < keep.size(); ++k) Q.row(static_cast<Index>(k)) = P.row(keep[k]);
  return Q;
}

}  // namespace kc::sampling
