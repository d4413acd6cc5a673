#include "kc/sampling/boundary.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

namespace {

/// A line end p on the cage (within eps of an edge): the boundary sample it becomes — a control
/// within eps, else the edge sample of that edge nearest p, moved along its edge to p (its weights
/// stay the edge's linear ones, 4.7) — or −1 when p is not on the cage.
Index boundarySampleAt(SampleSet& S, const Vec2& p, double eps) {
  Index best = -1;
  double bestDistance = std::numeric_limits<double>::infinity();
  int ea = -1, eb = -1;
  for (Index i = 0; i < S.size(); ++i) {
    const SampleKind k = S.kind[std::size_t(i)];
    if (k == SampleKind::Control && (Vec2(S.X.row(i)) - p).norm() <= eps) return i;
    if (k != SampleKind::Edge) continue;
    const Vec2 A = S.X.row(S.edge(i, 0)), B = S.X.row(S.edge(i, 1));
    if (pointSegmentDistance(p, A, B) > eps) continue;
    const double d = (Vec2(S.X.row(i)) - p).norm();
    if (d < bestDistance) best = i, bestDistance = d, ea = S.edge(i, 0), eb = S.edge(i, 1);
  }
  if (best < 0) return -1;
  const Vec2 A = S.X.row(ea), B = S.X.row(eb);
  const double t = std::clamp((p - A).dot(B - A) / (B - A).squaredNorm(), 0.0, 1.0);
  S.X.row(best) = ((1.0 - t) * A + t * B).transpose();
  return best;
}

}  // namespace

void appendLineSamples(SampleSet& S, std::span<const StructureLine> lines, const SizingField& sizing) {
  const std::vector<LineContact> contacts = lines.size() > 1 ? lineContacts(lines) : std::vector<LineContact>{};
  // Line ends on the cage share its boundary sample (only where a line touches the cage).
  double extent = 1.0;
  for (Index i = 0; i < S.size(); ++i) extent = std::max(extent, S.X.row(i).cwiseAbs().maxCoeff());
  const double eps = 1e-9 * extent;
  std::vector<std::array<Index, 2>> onCage(lines.size(), {-1, -1});
  bool touches = false;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    onCage[k] = {boundarySampleAt(S, lines[k].a, eps), boundarySampleAt(S, lines[k].b, eps)};
    touches = touches || onCage[k][0] >= 0 || onCage[k][1] >= 0;
  }
  if (contacts.empty() && !touches) {
    for (const StructureLine& l : lines) {
      const Index first = S.X.rows();
      appendSamples(S, lineSamplePoints(l, sizing), SampleKind::Line);
      std::vector<Index> idx(static_cast<std::size_t>(S.X.rows() - first));
      for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = first + static_cast<Index>(k);
      S.lines.push_back(std::move(idx));
    }
    return;
  }
  // Lines that meet share one sample there: each line is divided between its ends and its contacts
  // (segmentDivision of every piece), a contact's sample made by the first line that reaches it; an
  // end on the cage is the boundary sample there.
  std::vector<Index> contactSample(contacts.size(), -1);
  auto addSample = [&](const Vec2& p) {
    Points P(1, 2);
    P.row(0) = p.transpose();
    appendSamples(S, P, SampleKind::Line);
    return S.X.rows() - 1;
  };
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const StructureLine& line = lines[k];
    // Nodes along the line: (parameter, contact or −1), the ends included.
    std::vector<std::pair<double, int>> nodes{{0.0, -1}, {1.0, -1}};
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      if (contacts[c].k == k) nodes.emplace_back(contacts[c].tk, static_cast<int>(c));
      if (contacts[c].l == k) nodes.emplace_back(contacts[c].tl, static_cast<int>(c));
    }
    std::sort(nodes.begin(), nodes.end());
    // One node per parameter: a contact replaces the plain end it falls on; contacts at one point share.
    std::vector<std::pair<double, std::vector<int>>> merged;
    for (const auto& [t, c] : nodes) {
      if (merged.empty() || t > merged.back().first) merged.push_back({t, {}});
      if (c >= 0) merged.back().second.push_back(c);
    }
    std::vector<Index> idx;
    auto nodeSample = [&](const std::pair<double, std::vector<int>>& node) {
      Index id = node.first == 0.0 ? onCage[k][0] : node.first == 1.0 ? onCage[k][1] : -1;
      for (int c : node.second)
        if (contactSample[std::size_t(c)] >= 0) id = contactSample[std::size_t(c)];
      if (id < 0) id = addSample(node.first == 0.0 ? line.a : node.first == 1.0 ? line.b : (1.0 - node.first) * line.a + node.first * line.b);
      for (int c : node.second) contactSample[std::size_t(c)] = id;
      return id;
    };
    idx.push_back(nodeSample(merged.front()));
    for (std::size_t n = 1; n < merged.size(); ++n) {
      const double t0 = merged[n - 1].first, t1 = merged[n].first;
      const Vec2 p0 = (1.0 - t0) * line.a + t0 * line.b, p1 = (1.0 - t1) * line.a + t1 * line.b;
      const std::vector<double> div = segmentDivision(p0, p1, sizing);
      for (std::size_t j = 1; j + 1 < div.size(); ++j) idx.push_back(addSample((1.0 - div[j]) * p0 + div[j] * p1));
      idx.push_back(nodeSample(merged[n]));
    }
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
