#pragma once
/// The pinned outside mode's fold repair. The pinned exterior map is first the harmonic extension
/// of the cage's displacement to the fixed image border (exterior_weights.h); where the cage moves
/// a lot, harmonic maps concentrate the stretch next to it and fold triangles of the background.
/// The repair moves only vertices strictly outside the cage (the "free" vertices); the points on
/// the cage and the image corners stay where the field and the frame put them, so the inside of
/// the cage and the corners do not change. On a mesh that follows the cage (cage_conforming_grid.h)
/// every free vertex off the border has a closed star of exterior triangles.
///
/// The border gives way where it must. With a frame (ExteriorRepairFrame), the non-corner border
/// vertices outside the cage are free too, but only to slide along the border or to move outward
/// (pixels beyond the image rectangle are off the canvas): the image rectangle is padded by a ring
/// of fixed "ghost" vertices at distance G outside it (G = how far the harmonic map reaches past
/// the frame, plus a margin of max(16 spacings, a quarter of the frame's longer side)), one ghost
/// per border vertex, joined to the border by ghost triangles that are never drawn. The ghost ring
/// closes each border vertex's star, so the local optimisation below stays a bounded linear
/// program, and keeps the border curve simple (a ghost triangle folds if the border crosses
/// itself). Where the deformed cage reaches past the border, no map with a fixed border is
/// one-to-one; with the ghost ring, one exists whenever the deformed cage is simple and leaves the
/// four corners outside it. Border vertices move only where the region reaches them, and only as
/// the barrier's relaxation needs.
///
/// 1. Region: the free vertices of exterior triangles with det J ≤ minJacobian, grown by `rings`
///    rings of free neighbours (regrown when a fold reaches the region's edge). A fold the outline
///    forces (the field's map turns a piece of the cage's outline back against the pieces beside
///    it on the same cage edge, so the background triangle on it folds wherever its free vertex
///    goes outside the deformed inside) is left out: its vertices stay at the harmonic positions
///    (ExteriorRepairReport::foldedForced).
/// 2. Untangling (Freitag & Plassmann's local optimisation): each region vertex v whose star has
///    a triangle with det J ≤ minJacobian moves to the point p maximising min_k det J_k(p) over the
///    triangles k of its star. det J_k(p) = (c_k + g_k·p) / (2 A_k) is affine in p, so this is a
///    2-D linear program, bounded because the star is closed; its optimum is where three of the
///    affine functions meet (all triples are tried: a star has ≤ ~12 triangles). For a border
///    vertex the program has one more constraint, n·(p − p₀) ≥ 0 (n the outward normal, p₀ its
///    rest position), so pairs of the affine functions meeting on the border line are tried too.
///    Gauss–Seidel sweeps until no region triangle is below minJacobian or `maxSweeps`.
/// 3. Continuation under a barrier: the region starts at the start positions (rest, or a
///    fold-free earlier result: ExteriorRepairStart) and moves in increments of at most 1/steps by
///    its harmonic displacement while the vertices around it move to start + s·(harmonic −
///    start), s from 0 to 1. A step that folds a region triangle is taken back and halved (down to
///    1/(16·steps)); a step that folds none is relaxed by `stepRelaxSweeps` sweeps of the
///    symmetric Dirichlet energy (exterior_relax.h), which grows without bound as a triangle
///    degenerates: the squeeze of the cage's move spreads over the region instead of collapsing
///    triangles, so the next step starts with room to move. Where a squeezed triangle (det J <
///    0.3) reaches the region's edge, the region grows by `rings` rings. Only a step that still
///    folds at the smallest size is untangled as in 2. After a step that folds nothing, the next
///    may double again. The work is budgeted (ExteriorRepairOptions::budget). Once the
///    continuation ends fold-free, the relaxation runs again over the region (`relaxSweeps`).
///    Outside the region the background is the harmonic one.
/// 4. Fallback: per connected part of the region, if the repair left a folded triangle around it,
///    the part goes back to the harmonic positions: a repair keeps only what it untangled. Folds
///    remain where no placement of the free vertices removes one — the deformed cage overlaps
///    itself or a corner; a partial repair there had spread the squeeze over the background and
///    dragged the border to leave one fold instead of many. The report counts what is left.

#include <cstdint>
#include <vector>

#include "kc/core/types.h"

namespace kc {

struct ExteriorRepairOptions {
  double minJacobian = 0.05;  ///< Target: every repaired triangle keeps det J ≥ this.
  int rings = 3;              ///< Rings of free neighbours added around the folded triangles.
  int steps = 32;             ///< Continuation steps from rest (0) to the harmonic positions (1).
  int warmSteps = 4;          ///< Continuation steps from an earlier result (ExteriorRepairStart).
  int maxSweeps = 30;         ///< Untangling sweeps per step (only a step that folds at the smallest size).
  int stepRelaxSweeps = 10;   ///< Relaxation sweeps over the region after each continuation step (0: none).
  /// Sweeps of the relaxation that spreads a squeeze over the region once it is fold-free
  /// (exterior_relax.h; stops earlier when the energy settles). 0: none.
  int relaxSweeps = 300;
  /// Work budget of the adaptive continuation, in vertex visits of its sweeps (untangling and
  /// relaxation): budget ×
  /// steps × maxSweeps × the first region's size (a fixed schedule whose every step runs out of
  /// sweeps costs 1, without the region growing). Once spent, the continuation jumps to the end
  /// and the fallback decides: this bounds the cost of poses no placement untangles.
  double budget = 4.0;
};

struct ExteriorRepairReport {
  Index foldedBefore = 0;  ///< Exterior triangles with det J ≤ 0 before the repair.
  /// Of foldedBefore, folds the outline forces: triangles on a piece of the cage's outline that the
  /// field's map turns back against the next piece of the same cage edge. The repair holds their
  /// vertices and leaves them folded.
  Index foldedForced = 0;
  Index foldedAfter = 0;   ///< … after it.
  Index foldedFixed = 0;   ///< Of foldedAfter, triangles with no free vertex (on the cage or the border only).
  Index regionVertices = 0;  ///< Vertices left moved (after the fallback).
  Index borderVertices = 0;  ///< Of those, border vertices (they slid along the border or moved outward).
  bool warmStart = false;    ///< The continuation started from an earlier result (ExteriorRepairStart).
  int sweeps = 0;            ///< Untangling sweeps run, over all steps.
  int retries = 0;           ///< Continuation steps taken back and halved (they left a fold).
  int relaxSweeps = 0;       ///< Relaxation sweeps run at the end (0: none, or the region kept a fold).
};

/// The image rectangle whose border vertices may give way (x0 < x1, y0 < y1: the rest positions
/// of the border vertices lie exactly on it).
struct ExteriorRepairFrame {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

/// The outward direction at a point of the frame's border: the side's unit normal, (±1, ±1) at a
/// corner, 0 off the border.
Vec2 exteriorOutwardAt(const ExteriorRepairFrame& f, const Vec2& p);

/// The exterior triangles around each vertex (CSR: triangles around[start[v] .. start[v+1]) of
/// vertex v; index t < exteriorTriangles is a mesh triangle, t ≥ exteriorTriangles the ghost
/// triangle t − exteriorTriangles) and the vertices the repair may move, built once per mesh.
struct ExteriorRepairTopology {
  std::vector<Index> start, around;
  /// 1: strictly outside the cage and off the border, in a triangle; 2: a border vertex (not a
  /// corner) outside the cage that may slide along the border or move outward; 0: fixed.
  std::vector<std::uint8_t> free;
  /// The border ring (empty without a frame, or when the mesh's boundary is not the frame's
  /// polygon): border vertex ids in order around the frame; ghost k (vertex id #V + k) lies at
  /// rest(ring[k]) + G·outward[k] (outward: the side's unit normal, (±1, ±1) at a corner).
  std::vector<int> ring;
  std::vector<Vec2> outward;
  Triangles ghosts;  ///< Two per ring edge (a, b): (a, b, ghost b), (a, ghost b, ghost a).
  ExteriorRepairFrame frame;
  double spacing = 0.0;  ///< Longest ring edge at rest (px).
};

/// Topology of triangles[0..exteriorTriangles) over rest.rows() vertices; `movable[v]` = 1 for the
/// vertices strictly outside the cage (#V). With a frame, border vertices among them may slide or
/// move outward (corners stay fixed) when the mesh's boundary is the frame's polygon, else they
/// are fixed; without a frame, the movable vertices are free as given (the caller leaves the
/// border out).
ExteriorRepairTopology exteriorRepairTopology(const Points& rest, const Triangles& triangles, Index exteriorTriangles,
                                              const std::vector<std::uint8_t>& movable, const ExteriorRepairFrame* frame = nullptr);

/// Where the continuation starts: an earlier result of the repair on the same mesh (#V×2, with no
/// fold outside the cage). Used while a pose is dragged: the next pose is close, so a few steps
/// from the previous picture replace the continuation from rest. The region is found as from rest
/// (from the harmonic map's folds); its vertices start at the earlier positions, the rest of the
/// mesh ends at the harmonic positions as always.
struct ExteriorRepairStart {
  const Points* positions = nullptr;
};

/// Repairs the folds of triangles[0..exteriorTriangles) in `deformed` (#V×2, the harmonic positions
/// on entry) as the file comment describes; restArea (#T, non-zero) gives det J = deformed / rest
/// signed area. Only free vertices change. `start`: see ExteriorRepairStart (null: from rest).
/// Cost: nothing beyond one pass over the
/// exterior triangles when none is folded; else O(region · sweeps · star³).
ExteriorRepairReport repairExteriorFolds(const Points& rest, Points& deformed, const Triangles& triangles, const ExteriorRepairTopology& topology,
                                         Index exteriorTriangles, const Eigen::VectorXd& restArea,
                                         const ExteriorRepairOptions& options = {}, const ExteriorRepairStart& start = {});

}  // namespace kc
