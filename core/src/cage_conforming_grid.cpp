#include "kc/core/cage_conforming_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kc/core/cage_edge_grid.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/parallel.h"

namespace kc {

CageConformingGrid cageConformingGrid(const std::vector<double>& xs, const std::vector<double>& ys, const Cage& cage,
                                      const std::vector<std::uint8_t>& gridExterior, const std::vector<std::uint8_t>& gridBand) {
  const int nx = int(xs.size()), ny = int(ys.size());
  if (nx < 2 || ny < 2 || gridExterior.size() != std::size_t(nx) * std::size_t(ny) ||
      (!gridBand.empty() && gridBand.size() != gridExterior.size()))
    throw std::invalid_argument("cage-conforming grid: the grid needs at least 2×2 vertices and one class per vertex");
  const Index ng = Index(nx) * ny;
  const double dx = xs[1] - xs[0], dy = ys[1] - ys[0];
  const double tol = 0.02 * std::min(dx, dy);
  const double x0 = xs.front(), x1 = xs.back(), y0 = ys.front(), y1 = ys.back();
  const auto inBox = [&](const Vec2& p) { return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1; };
  const auto edges = cageEdges(cage);
  const Points& C = cage.C;

  CageConformingGrid out;
  out.gridVertices = ng;
  out.tolerance = tol;
  out.unused.assign(std::size_t(ng), 0);
  const CageEdgeGrid edgeGrid(cage, std::max(dx, dy));
  parallelFor(ng, [&](Index v) {
    const Vec2 p(xs[std::size_t(v % nx)], ys[std::size_t(v / nx)]);
    out.unused[std::size_t(v)] = edgeGrid.distance(p, 2.0 * tol) < tol ? 1 : 0;
  }, 1024);

  // Points on the cage: the cage points inside the image, then per edge its crossings with the
  // grid lines (those within tol of a kept end point or of the previous crossing are left out).
  std::vector<Vec2> cagePts;
  std::vector<int> pointRow(std::size_t(C.rows()), -1);
  for (Index i = 0; i < C.rows(); ++i)
    if (inBox(C.row(i))) {
      pointRow[std::size_t(i)] = int(ng + Index(cagePts.size()));
      cagePts.emplace_back(C.row(i));
    }
  std::vector<std::array<int, 2>> segments;
  std::vector<std::pair<double, Vec2>> along;  // (edge parameter, point)
  for (const auto& [a, b] : edges) {
    const Vec2 A = C.row(a), B = C.row(b), d = B - A;
    along.clear();
    for (int axis = 0; axis < 2; ++axis) {
      const std::vector<double>& lines = axis == 0 ? xs : ys;
      const double lo = std::min(A(axis), B(axis)), hi = std::max(A(axis), B(axis));
      if (d(axis) == 0.0) continue;  // parallel to these lines (on one of them: its points are the grid's)
      for (auto it = std::lower_bound(lines.begin(), lines.end(), lo); it != lines.end() && *it <= hi; ++it) {
        const double s = (*it - A(axis)) / d(axis);
        if (!(s > 0.0 && s < 1.0)) continue;
        Vec2 p = A + s * d;
        p(axis) = *it;
        if (inBox(p)) along.emplace_back(s, p);
      }
    }
    std::sort(along.begin(), along.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
    // The chain of points along the edge: A (when in the image), the crossings, B.
    std::vector<std::pair<int, Vec2>> chain;
    if (pointRow[std::size_t(a)] >= 0) chain.emplace_back(pointRow[std::size_t(a)], A);
    for (const auto& [s, p] : along) {
      if (!chain.empty() && (p - chain.back().second).norm() < tol) continue;
      if (pointRow[std::size_t(b)] >= 0 && (p - B).norm() < tol) continue;
      chain.emplace_back(int(ng + Index(cagePts.size())), p);
      cagePts.push_back(p);
    }
    if (pointRow[std::size_t(b)] >= 0) chain.emplace_back(pointRow[std::size_t(b)], B);
    // Pieces inside the image are constraints (a piece between two crossings of the border that
    // runs outside the image is not).
    for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
      const Vec2 mid = 0.5 * (chain[k].second + chain[k + 1].second);
      if (mid.x() >= x0 - tol && mid.x() <= x1 + tol && mid.y() >= y0 - tol && mid.y() <= y1 + tol)
        segments.push_back({chain[k].first, chain[k + 1].first});
    }
  }

  // Triangulate the used grid vertices and the cage points (compact numbering), map back.
  std::vector<int> row;  // compact index → mesh row
  for (Index v = 0; v < ng; ++v)
    if (!out.unused[std::size_t(v)]) row.push_back(int(v));
  const Index usedGrid = Index(row.size());
  for (std::size_t k = 0; k < cagePts.size(); ++k) row.push_back(int(ng + Index(k)));
  std::vector<int> compact(std::size_t(ng) + cagePts.size(), -1);
  for (std::size_t k = 0; k < row.size(); ++k) compact[std::size_t(row[k])] = int(k);
  Points P(Index(row.size()), 2);
  for (Index k = 0; k < usedGrid; ++k) P.row(k) << xs[std::size_t(row[std::size_t(k)] % nx)], ys[std::size_t(row[std::size_t(k)] / nx)];
  for (std::size_t k = 0; k < cagePts.size(); ++k) P.row(usedGrid + Index(k)) = cagePts[k];
  for (auto& [a, b] : segments) a = compact[std::size_t(a)], b = compact[std::size_t(b)];
  const ConstrainedTriangulation cdt = constrainedTriangulation(P, segments);
  for (Index k = P.rows(); k < cdt.V.rows(); ++k) {  // crossings of cage edges with each other
    row.push_back(int(ng + Index(cagePts.size())));
    cagePts.emplace_back(cdt.V.row(k));
  }

  const Index nv = ng + Index(cagePts.size());
  out.V.resize(nv, 2);
  for (Index v = 0; v < ng; ++v) out.V.row(v) << xs[std::size_t(v % nx)], ys[std::size_t(v / nx)];
  for (std::size_t k = 0; k < cagePts.size(); ++k) out.V.row(ng + Index(k)) = cagePts[k];
  out.onCage.assign(std::size_t(nv), 0);
  std::fill(out.onCage.begin() + ng, out.onCage.end(), 1);
  out.unused.resize(std::size_t(nv), 0);

  // Classify: by the triangle's grid vertices (at least tol from the cage, so their class is
  // sure; inside when none is exterior, which matters only at a stick band's edge), else by the
  // centroid: inside a loop, or in a stick band (the band's flag at the nearest grid vertex).
  Triangles outside, inside;
  const auto nearestGrid = [&](const Vec2& p) {
    const auto nearest = [](const std::vector<double>& axis, double x) {
      const auto it = std::lower_bound(axis.begin(), axis.end(), x);
      if (it == axis.begin()) return 0;
      if (it == axis.end()) return int(axis.size()) - 1;
      return int(it - axis.begin()) - (x - *(it - 1) < *it - x ? 1 : 0);
    };
    return std::size_t(nearest(ys, p.y())) * std::size_t(nx) + std::size_t(nearest(xs, p.x()));
  };
  for (const auto& t : cdt.T) {
    const std::array<int, 3> m{row[std::size_t(t[0])], row[std::size_t(t[1])], row[std::size_t(t[2])]};
    bool in = true, anyGrid = false;
    for (const int v : m)
      if (v < ng) anyGrid = true, in = in && !gridExterior[std::size_t(v)];
    if (!anyGrid) {
      const Vec2 centroid = (out.V.row(m[0]) + out.V.row(m[1]) + out.V.row(m[2])) / 3.0;
      in = (hasInterior(cage) && insideCage(cage, centroid)) || (!gridBand.empty() && gridBand[nearestGrid(centroid)]);
    }
    (in ? inside : outside).push_back(m);
  }
  out.outsideTriangles = Index(outside.size());
  out.T = std::move(outside);
  out.T.insert(out.T.end(), inside.begin(), inside.end());
  return out;
}

}  // namespace kc
