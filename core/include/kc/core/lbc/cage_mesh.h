#pragma once
/// The LBC domain mesh (LBC paper §4): a constrained Delaunay triangulation of the cage interior,
/// refined by a Delaunay mesher, whose vertices 0..m−1 are the control points in cage order and
/// whose other boundary vertices carry the cage edge they lie on and their edge parameter.

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/sizing.h"
#include "kc/core/types.h"
#include "kc/core/solve.h"

namespace kc {

struct CageMeshOptions {
  double spacing = 8.0;          ///< h: longest triangle edge; cage edges are pre-split at ≈ h (pixels).
  double minAngleDegrees = 20.0; ///< Smallest triangle angle the mesher aims for (≤ 20.7° always terminates).
  Index maxVertices = 2'000'000;  ///< The mesher stops with status TooLarge past this count.
  /// The local spacing h(x) of a graded mesh (featureSizing): cage edges are divided by
  /// segmentDivision and a triangle is refined while its longest edge exceeds min(spacing, h(c))
  /// at its centroid c. Null: the uniform mesh at `spacing`.
  std::shared_ptr<const SizingField> sizing;
};

/// A triangle mesh of the cage interior, vertices ordered controls | cage-edge points | interior.
struct CageMesh {
  Points V;                 ///< #V×2 vertex positions; rows 0..m−1 are the control points C.
  Triangles T;              ///< Triangles (vertex indices), counter-clockwise in the (x, y) axes.
  Index controls = 0;       ///< m.
  Index boundary = 0;       ///< nb: rows 0..nb−1 lie on the cage (controls, then edge points).
  /// #V×2: for edge points (rows m..nb−1) the control indices (k, l) of their cage edge; (−1, −1) else.
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> edge;
  /// #V: edge parameter t of an edge point, V = (1 − t) c_k + t c_l exactly; 0 elsewhere.
  Eigen::VectorXd t;
  SolveStatus status = SolveStatus::Ok;  ///< Ok or TooLarge (MeshOptions::maxVertices).

  Index size() const { return V.rows(); }
  Index interior() const { return V.rows() - boundary; }
};

/// Meshes the interior of a closed cage (paper §4): every cage edge is split into
/// ⌈|c_l − c_k|/h⌉ equal pieces (with a sizing field: segmentDivision's pieces at the local
/// spacing), the pieces are the constraints of a constrained Delaunay triangulation, and the
/// Delaunay mesher refines the interior to edges ≤ h (≤ min(h, h(centroid)) with a sizing field)
/// and angles ≥ minAngleDegrees. Points the mesher adds on the cage are recorded with their edge and edge
/// parameter (and put exactly on the edge). Throws std::invalid_argument for an open cage, an
/// edge graph that is not the cage polygon, or an invalid cage (validateCage), or a spacing that
/// is not positive and finite. On status TooLarge the mesh is empty.
CageMesh meshCageInterior(const Cage& cage, const CageMeshOptions& options = {});

/// A constrained Delaunay triangulation of `points` (#P×2) in which every segment (a pair of
/// point indices) is a union of triangle edges: the triangles cover the points' convex hull and
/// none crosses a segment. Vertices: rows 0..#P−1 are `points` (a point equal to an earlier one is
/// merged into it and used by no triangle); where two segments cross, the crossing is added as a
/// further row. Triangles are counter-clockwise in the (x, y) axes. Throws std::invalid_argument
/// for a segment index out of range or a non-finite point.
struct ConstrainedTriangulation {
  Points V;     ///< #V×2, #V ≥ #P.
  Triangles T;  ///< Vertex indices into V.
};
ConstrainedTriangulation constrainedTriangulation(const Points& points, const std::vector<std::array<int, 2>>& segments);

/// Vertices of the uniform mesh at spacing h (meshCageInterior without a sizing field), estimated
/// without meshing: about 2.45 per h² of the cage's area (Delaunay refinement to edges ≤ h) plus
/// the cage's edge points, perimeter / h.
double estimateMeshVertices(const Cage& cage, double spacing);

/// A spacing h for which meshCageInterior gives about `targetVertices` vertices (for benchmarks
/// and for binding by vertex count): h from the cage area, corrected once by a trial mesh.
double spacingForVertexCount(const Cage& cage, Index targetVertices, double minAngleDegrees = 20.0);

}  // namespace kc
