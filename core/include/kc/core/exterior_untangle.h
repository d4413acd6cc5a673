#pragma once
/// The pinned outside mode's fold repair. The pinned exterior map is first the harmonic extension
/// of the cage's displacement to the fixed image border (exterior_weights.h); where the cage moves
/// a lot, harmonic maps concentrate the stretch next to it and fold triangles of the background.
/// The repair moves only vertices strictly outside the cage and off the image border (the
/// "free" vertices); the points on the cage and the border stay where the field and the frame put
/// them, so the inside of the cage and the corners do not change. On a mesh that follows the cage
/// (cage_conforming_grid.h) every free vertex has a closed star of exterior triangles.
///
/// 1. Region: the free vertices of exterior triangles with det J ≤ minJacobian, grown by `rings`
///    rings of free neighbours (regrown when a fold reaches the region's edge).
/// 2. Untangling (Freitag & Plassmann's local optimisation): each region vertex v whose star has
///    a triangle with det J ≤ minJacobian moves to the point p maximising min_k det J_k(p) over the
///    triangles k of its star. det J_k(p) = (c_k + g_k·p) / (2 A_k) is affine in p, so this is a
///    2-D linear program, bounded because the star is closed; its optimum is where three of the
///    affine functions meet (all triples are tried: a star has ≤ ~12 triangles). Gauss–Seidel
///    sweeps until no region triangle is below minJacobian or `maxSweeps`.
/// 3. Smoothing: the correction δ(v) = p(v) − h(v) (h the harmonic position) is relaxed towards
///    its neighbour average (a discrete harmonic correction that vanishes at the region's edge),
///    each step shortened (1, 1/2, 1/4, …) until the star keeps det J ≥ minJacobian, so the
///    smoothing never folds. The repaired background therefore equals the harmonic one outside the
///    region and bends smoothly inside it.
///
/// The untangling runs as a continuation: the region starts at rest (fold-free) and moves in
/// `steps` equal increments of its harmonic displacement while the vertices around it move to
/// rest + s·(harmonic − rest), s = 1/steps … 1; each step is untangled and smoothed, so the
/// configuration stays close to a fold-free one.
///
/// 4. Fallback: per connected part of the region, if the repair left more folded triangles around
///    it than the harmonic map had, the part goes back to the harmonic positions. That happens
///    where no placement of the free vertices removes a fold — the deformed cage crosses the
///    fixed border (the cage pushed past the image border) or overlaps itself — and the max–min
///    moves only spread it. The report counts what is left.

#include <cstdint>
#include <vector>

#include "kc/core/types.h"

namespace kc {

struct ExteriorRepairOptions {
  double minJacobian = 0.05;  ///< Target: every repaired triangle keeps det J ≥ this.
  int rings = 3;              ///< Rings of free neighbours added around the folded triangles.
  int steps = 32;             ///< Continuation steps from rest (0) to the harmonic positions (1).
  int maxSweeps = 30;         ///< Untangling sweeps over the region per step.
  int smoothSweeps = 3;       ///< Smoothing sweeps over the region per step.
};

struct ExteriorRepairReport {
  Index foldedBefore = 0;  ///< Exterior triangles with det J ≤ 0 before the repair.
  Index foldedAfter = 0;   ///< … after it.
  Index foldedFixed = 0;   ///< Of foldedAfter, triangles with no free vertex (on the cage or the border only).
  Index regionVertices = 0;  ///< Vertices left moved (after the fallback).
  int sweeps = 0;            ///< Untangling sweeps run, over all steps.
};

/// The exterior triangles around each vertex (CSR: triangles around[start[v] .. start[v+1]) of
/// vertex v) and the vertices the repair may move, built once per mesh.
struct ExteriorRepairTopology {
  std::vector<Index> start, around;
  std::vector<std::uint8_t> free;  ///< 1: strictly outside the cage, off the border, in a triangle.
};

/// Topology of triangles[0..exteriorTriangles) over `vertices` vertices; `movable[v]` = 1 for the
/// vertices strictly outside the cage and off the image border (#V).
ExteriorRepairTopology exteriorRepairTopology(const Triangles& triangles, Index exteriorTriangles, Index vertices,
                                              const std::vector<std::uint8_t>& movable);

/// Repairs the folds of triangles[0..exteriorTriangles) in `deformed` (#V×2, the harmonic positions
/// on entry) as the file comment describes; restArea (#T, non-zero) gives det J = deformed / rest
/// signed area. Only free vertices change. Cost: nothing beyond one pass over the exterior
/// triangles when none is folded; else O(region · sweeps · star³).
ExteriorRepairReport repairExteriorFolds(const Points& rest, Points& deformed, const Triangles& triangles, const ExteriorRepairTopology& topology,
                                         Index exteriorTriangles, const Eigen::VectorXd& restArea,
                                         const ExteriorRepairOptions& options = {});

}  // namespace kc
