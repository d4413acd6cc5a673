#pragma once
/// How a deformation treats the picture outside the cage: how far the background moves at given
/// distances from the cage, whether the image corners stay, the range of the weights there and
/// fold-overs that lie wholly outside the cage. Works for every outside mode of the warp mesh.

#include <vector>

#include "kc/core/warp_mesh.h"

namespace kc {

/// Displacement |f(v) − v| of the mesh vertices outside the cage whose distance to the cage is
/// within `halfWidth` of `distance`.
struct OutsideBand {
  double distance = 0.0, halfWidth = 0.0;
  Index vertices = 0;
  double mean = 0.0, max = 0.0;
};

struct OutsideMotion {
  /// Largest displacement of a vertex at one of the picture's four corners (px; (−0.5, −0.5) and
  /// (width − 0.5, height − 0.5) diagonally, the warp mesh's frame); 0 when the mesh has none there
  /// (fixed and transparent meshes of the inside alone).
  double cornerMax = 0.0;
  /// Largest displacement of a vertex on the picture's frame (px; pinned mode: where the fold repair
  /// let the border give way, exterior_untangle.h), and how many frame vertices moved at all.
  double borderMax = 0.0;
  Index borderMoved = 0;
  std::vector<OutsideBand> bands;  ///< One per requested distance.
  double minWeight = 0.0;          ///< Range of w_i (i < m; the pinned anchor excluded) at vertices
  double maxWeight = 0.0;          ///< outside the cage, as stored by the mesh (compact weights).
  Index verticesOutside = 0;
  /// Flipped triangles (det J ≤ 0) outside the cage: in Pinned mode the triangles of the mesh's
  /// outside (WarpMesh::outsideTriangles(), those touching the cage included); else those with all
  /// three vertices outside the cage.
  Index flippedOutside = 0;
  /// Pinned mode: of flippedOutside, those with a vertex on the cage, and those whose deformed
  /// triangle lies under the deformed inside (its corners and centroid in deformed inside
  /// triangles), which the inside, drawn on top, hides.
  Index flippedOnCage = 0, flippedCovered = 0;
  Index flippedTotal = 0;
};

/// Measures the last deform() of `mesh` (vertices outside: in Pinned mode the mesh's exterior
/// vertices, points on the cage excluded; else outside a closed cage by the even-odd rule, every
/// vertex for open cages). Bands of half width `halfWidth` pixels around each of `distances`.
/// Cost O(#V · #edges). Throws std::invalid_argument when the mesh has no weights.
OutsideMotion measureOutside(const WarpMesh& mesh, const std::vector<double>& distances = {50.0, 200.0},
                             double halfWidth = 5.0);

}  // namespace kc
