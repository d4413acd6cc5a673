#pragma once
/// The pinned outside mode's fold guard. The pinned exterior map is f(x) = x + d(x) with d the
/// harmonic extension of the cage's displacement, d = 0 on the image border. Where a pose pushes
/// the cage towards the border by more than the background between them (a hand dragged over the
/// edge of the picture), no map that keeps the border fixed and follows the cage can be
/// one-to-one: the strip between them must fold. The guard holds the background back there
/// instead: each exterior vertex v gets a scale s_v ∈ [0, 1] and moves to v + s_v d(v), with s_v
/// multiplied by 3/4 on the vertices of every exterior triangle whose det J ≤ minJacobian, round
/// after round, until none is left (s = 1 elsewhere: an unfolded pose is not changed). Vertices
/// next to the cage (of triangles across it) are scaled only once a folded triangle's other
/// vertices are nearly at rest, so the background stays attached to the cage wherever it can.
/// A held-back vertex also holds back its neighbours away from the cage, so the scale rises from
/// it no faster than 1 over twice the neighbour's displacement: the background bends smoothly
/// instead of kinking (the added stretch |d|·|∇s| stays below 1/2). The picture inside the
/// cage, drawn over its background, covers the part that was held back, as a hand covers the
/// background it slides over. It terminates (a scale below 1/1024 becomes 0 and is not scaled
/// again), and leaves no guarded triangle folded: one whose three scales reach 0 is at rest, det J = 1.
/// The price: triangles across the cage next to a held-back vertex may fold (they are drawn under
/// the inside); DeformReport::flippedTriangles counts them.

#include <cstdint>
#include <vector>

#include "kc/core/types.h"

namespace kc {

struct FoldGuardReport {
  Index foldedBefore = 0;     ///< Guarded triangles with det J ≤ minJacobian before the guard.
  Index scaledVertices = 0;   ///< Vertices whose displacement was scaled down (s_v < 1).
  double minScale = 1.0;      ///< min_v s_v.
  int rounds = 0;
};

/// The guarded triangles around each vertex (CSR: triangles around[start[v] .. start[v+1]) of
/// vertex v), built once per mesh.
struct FoldGuardTopology {
  std::vector<Index> start, around;
};
/// Topology of triangles[0..guardedTriangles) over `vertices` vertices.
FoldGuardTopology foldGuardTopology(const Triangles& triangles, Index guardedTriangles, Index vertices);

/// Applies the guard (see the file comment) to `deformed` (#V×2, the positions f(v) of `rest`,
/// #V×2). Guarded triangles: triangles[0..guardedTriangles) (their vertices must all be movable:
/// movable[v] = 1, or 2 for a vertex next to the cage, scaled last); det J = deformed / rest signed
/// area with rest areas `restArea` (#T, non-zero); `topology` from foldGuardTopology(). Only
/// movable vertices of those triangles change. Cost O(guarded triangles) per round, and
/// nothing when no guarded triangle is folded.
FoldGuardReport guardExteriorFolds(const Points& rest, Points& deformed, const Triangles& triangles,
                                   const FoldGuardTopology& topology, Index guardedTriangles,
                                   const Eigen::VectorXd& restArea, const std::vector<std::uint8_t>& movable,
                                   double minJacobian = 0.05);

}  // namespace kc
