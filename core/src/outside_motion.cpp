#include "kc/core/outside_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "kc/core/parallel.h"

namespace kc {
namespace {

/// True when p lies in (or within round-off of) a deformed inside triangle of the pinned mesh.
bool inDeformedInside(const WarpMesh& mesh, const Vec2& p) {
  const Points& F = mesh.deformedVertices();
  const auto& T = mesh.triangles();
  for (std::size_t t = std::size_t(mesh.outsideTriangles()); t < T.size(); ++t) {
    const Vec2 a = F.row(T[t][0]), b = F.row(T[t][1]), c = F.row(T[t][2]);
    if (p.x() < std::min({a.x(), b.x(), c.x()}) - 1e-9 || p.x() > std::max({a.x(), b.x(), c.x()}) + 1e-9 ||
        p.y() < std::min({a.y(), b.y(), c.y()}) - 1e-9 || p.y() > std::max({a.y(), b.y(), c.y()}) + 1e-9)
      continue;
    const auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
    const double area = cross(b - a, c - a);
    if (area == 0.0) continue;
    const double l0 = cross(b - p, c - p) / area, l1 = cross(c - p, a - p) / area, l2 = cross(a - p, b - p) / area;
    if (l0 >= -1e-9 && l1 >= -1e-9 && l2 >= -1e-9) return true;
  }
  return false;
}

/// True when the deformed triangle t lies under the deformed inside: its corners and centroid do.
bool coveredByInside(const WarpMesh& mesh, const std::array<int, 3>& t) {
  const Points& F = mesh.deformedVertices();
  const Vec2 a = F.row(t[0]), b = F.row(t[1]), c = F.row(t[2]);
  return inDeformedInside(mesh, a) && inDeformedInside(mesh, b) && inDeformedInside(mesh, c) &&
         inDeformedInside(mesh, (a + b + c) / 3.0);
}

}  // namespace

OutsideMotion measureOutside(const WarpMesh& mesh, const std::vector<double>& distances, double halfWidth) {
  if (!mesh.hasWeights()) throw std::invalid_argument("outside motion: the warp mesh has no weights");
  const Points& R = mesh.restVertices();
  const Points& F = mesh.deformedVertices();
  const Cage& cage = mesh.cage();
  const Index nv = R.rows(), m = cage.size();
  std::vector<std::uint8_t> outside(std::size_t(nv), 0);
  std::vector<double> dist(std::size_t(nv), 0.0);
  // Pinned mode: the mesh's own classification (points on the cage belong to the inside).
  const ExteriorWeights* ext = mesh.exteriorWeights();
  const CageQueries queries(cage);
  parallelFor(nv, [&](Index v) {
    const Vec2 p = R.row(v);
    outside[std::size_t(v)] = ext ? ext->exterior[std::size_t(v)] : (queries.inside(p) ? 0 : 1);
    dist[std::size_t(v)] = queries.distance(p);
  }, 256);

  OutsideMotion out;
  out.minWeight = std::numeric_limits<double>::infinity();
  out.maxWeight = -std::numeric_limits<double>::infinity();
  for (const double d : distances) out.bands.push_back({d, halfWidth});
  // The picture's frame (the grid's outer lines, gridAxis), not the mesh's extent: a mesh of the
  // inside alone (fixed, transparent) has no vertex there, and its extreme vertices are the cage's.
  const double x0 = -0.5, x1 = mesh.width() - 0.5, y0 = -0.5, y1 = mesh.height() - 0.5;
  const auto& W = mesh.weights();
  for (Index v = 0; v < nv; ++v) {
    const double move = (F.row(v) - R.row(v)).norm();
    if ((R(v, 0) == x0 || R(v, 0) == x1) && (R(v, 1) == y0 || R(v, 1) == y1)) out.cornerMax = std::max(out.cornerMax, move);
    if (R(v, 0) == x0 || R(v, 0) == x1 || R(v, 1) == y0 || R(v, 1) == y1) {
      out.borderMax = std::max(out.borderMax, move);
      out.borderMoved += move > 0.0;
    }
    if (!outside[std::size_t(v)]) continue;
    ++out.verticesOutside;
    for (WarpMesh::SparseWeights::InnerIterator it(W, v); it; ++it)
      if (it.col() < m) {
        out.minWeight = std::min(out.minWeight, it.value());
        out.maxWeight = std::max(out.maxWeight, it.value());
      }
    for (OutsideBand& b : out.bands)
      if (std::abs(dist[std::size_t(v)] - b.distance) <= b.halfWidth) {
        ++b.vertices;
        b.mean += move;
        b.max = std::max(b.max, move);
      }
  }
  for (OutsideBand& b : out.bands)
    if (b.vertices > 0) b.mean /= double(b.vertices);
  if (out.verticesOutside == 0) out.minWeight = out.maxWeight = 0.0;
  // Weights absent from a sparse row are 0, which is in the range whenever a row has fewer than m.
  out.minWeight = std::min(out.minWeight, 0.0);
  const auto& T = mesh.triangles();
  for (std::size_t t = 0; t < T.size(); ++t) {
    if (mesh.jacobians()(Index(t)) > 0.0) continue;
    ++out.flippedTotal;
    const bool out3 = outside[std::size_t(T[t][0])] && outside[std::size_t(T[t][1])] && outside[std::size_t(T[t][2])];
    if (!(ext ? Index(t) < mesh.outsideTriangles() : out3)) continue;
    ++out.flippedOutside;
    if (ext && !out3) ++out.flippedOnCage;
    if (ext && coveredByInside(mesh, T[t])) ++out.flippedCovered;
  }
  return out;
}

}  // namespace kc
