#pragma once
/// The pinned outside mode's warp mesh: the regular grid over the image, re-triangulated so that
/// its edges follow the cage. Every cage point in the image is a vertex, every cage edge is a
/// chain of mesh edges (split where it crosses the grid lines), so each triangle lies wholly
/// inside or wholly outside the cage. The picture inside the cage then depends only on vertices
/// inside or on the cage, and the outside can be changed (the fold guard) without touching it.

#include <cstdint>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc {

struct CageConformingGrid {
  /// #V×2: rows 0..gridVertices−1 are the grid vertices (row j·nx + i at (xs[i], ys[j])), then the
  /// points on the cage: cage points inside the image, crossings of cage edges with grid lines,
  /// and any crossings of cage edges with each other.
  Points V;
  Index gridVertices = 0;
  /// Triangles (counter-clockwise in the (x, y) axes), those outside the cage first.
  Triangles T;
  Index outsideTriangles = 0;  ///< T[0..outsideTriangles) lie outside the cage, the rest inside.
  /// Per vertex: 1 for the points on the cage (rows ≥ gridVertices).
  std::vector<std::uint8_t> onCage;
  /// Per vertex: 1 for a grid vertex closer than `tolerance` to the cage, left out of the
  /// triangulation (a point on the cage next to it takes its place); no triangle uses it.
  std::vector<std::uint8_t> unused;
  double tolerance = 0.0;
};

/// The cage-conforming triangulation of the grid xs × ys (increasing, uniform steps) for `cage`
/// (validated by the caller; closed cages by the even-odd rule, open sticks have no inside).
/// `gridExterior` (#xs·#ys, grid order) classifies the grid vertices (1 outside the cage), as
/// pinnedExteriorWeights() does (vertices in a stick band count as inside); `gridBand` (empty, or
/// one flag per grid vertex) marks the stick band. A triangle is inside when none of its grid
/// vertices is exterior; one with all three vertices on the cage is inside when its centroid is
/// inside a loop or its nearest grid vertex is in the band. Grid vertices within tolerance = 0.02·spacing of
/// the cage are left out, and so are crossings within it of a cage point, so that no triangle is
/// a sliver. A constrained Delaunay triangulation (CGAL, cage_mesh.h) with the cage-edge pieces as
/// constraints; cost O(#V log #V), once per mesh.
CageConformingGrid cageConformingGrid(const std::vector<double>& xs, const std::vector<double>& ys, const Cage& cage,
                                      const std::vector<std::uint8_t>& gridExterior,
                                      const std::vector<std::uint8_t>& gridBand = {});

}  // namespace kc
