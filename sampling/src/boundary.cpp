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

SampleSet boundarySamples(const Cage& cage, double h) { return boundarySamples(cage, SizingField::uniform(h)); }

SampleSet boundarySamples(const Cage& cage, const SizingField& sizing) {
  const Index m = cage.size();
  const auto edges = cageEdges(cage);
  std::vector<std::vector<double>> division;
  division.reserve(edges.size());
  Index total = m;
  for (const auto& [a, b] : edges) {
    division.push_back(segmentDivision(cage.C.row(a), cage.C.row(b), sizing));
    total += static_cast<Index>(division.back().size()) - 2;
  }

  SampleSet S;
  S.X.resize(total, 2);
  S.kind.assign(static_cast<std::size_t>(total), SampleKind::Edge);
  S.edge.setConstant(total, 2, -1);
  S.X.topRows(m) = cage.C;
  std::fill(S.kind.begin(), S.kind.begin() + m, SampleKind::Control);
  Index row = m;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [a, b] = edges[e];
    const Vec2 A = cage.C.row(a), B = cage.C.row(b);
    const std::vector<double>& t = division[e];
    for (std::size_t k = 1; k + 1 < t.size(); ++k) {
      S.X.row(row) = ((1.0 - t[k]) * A + t[k] * B).transpose();
      S.edge(row, 0) = a;
      S.edge(row, 1) = b;
      ++row;
    }
  }
  return S;
}

Points framePoints(const Rect& domain, double h) { return framePoints(domain, SizingField::uniform(h)); }

Points framePoints(const Rect& domain, const SizingField& sizing) {
  // Counter-clockwise sides; the coordinate that is constant along a side is copied exactly so
  // every point lies on the rectangle (no rounding outside it).
  const Vec2 c00(domain.x0, domain.y0), c10(domain.x1, domain.y0), c11(domain.x1, domain.y1), c01(domain.x0, domain.y1);
  const std::array<std::array<Vec2, 2>, 4> sides{{{c00, c10}, {c10, c11}, {c11, c01}, {c01, c00}}};
  auto lerp = [](double a, double b, double t) { return std::clamp((1.0 - t) * a + t * b, std::min(a, b), std::max(a, b)); };
  std::vector<Vec2> pts;
  for (int side = 0; side < 4; ++side) {
    const auto& [A, B] = sides[static_cast<std::size_t>(side)];
    const std::vector<double> t = segmentDivision(A, B, sizing);
    for (std::size_t k = 0; k + 1 < t.size(); ++k) {
      if (side % 2 == 0) pts.emplace_back(lerp(A.x(), B.x(), t[k]), A.y());
      else pts.emplace_back(A.x(), lerp(A.y(), B.y(), t[k]));
    }
  }
  Points P(static_cast<Index>(pts.size()), 2);
  for (std::size_t k = 0; k < pts.size(); ++k) P.row(static_cast<Index>(k)) = pts[k].transpose();
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
  appendLineSamples(S, lines, SizingField::uniform(h));
}

void appendLineSamples(SampleSet& S, std::span<const StructureLine> lines, const SizingField& sizing) {
  for (const StructureLine& l : lines) {
    const Index first = S.X.rows();
    appendSamples(S, lineSamplePoints(l, sizing), SampleKind::Line);
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
  return dropNearCage(cage, P, SizingField::uniform(minDistance), 1.0);
}

Points dropNearCage(const Cage& cage, const Points& P, const SizingField& sizing, double fraction) {
  const CageEdgeGrid locator(cage, std::max(fraction * sizing.hMax(), 1e-9));
  std::vector<Index> keep;
  keep.reserve(static_cast<std::size_t>(P.rows()));
  for (Index i = 0; i < P.rows(); ++i) {
    const double minDistance = sizing.graded() ? fraction * sizing(P.row(i)) : fraction * sizing.hMax();
    if (locator.distance(P.row(i), minDistance) >= minDistance) keep.push_back(i);
  }
  Points Q(static_cast<Index>(keep.size()), 2);
  for (std::size_t k = 0; k < keep.size(); ++k) Q.row(static_cast<Index>(k)) = P.row(keep[k]);
  return Q;
}

}  // namespace kc::sampling
