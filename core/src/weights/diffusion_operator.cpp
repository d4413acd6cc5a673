// The cage-aware diffusion operator of the initial weights (thesis 4.11–4.13) and its reachability.
#include "diffusion_operator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/cage_edge_grid.h"
#include "kc/core/parallel.h"
#include "../sparse_lists.h"

namespace kc::detail {
namespace {

/// Exact: true when the segment a–b crosses the cage (kc::segmentCrossesCage); only segments that
/// come within `tol` of an edge of the grid pay for the exact, O(#edges) test.
bool crossesCage(const CageQueries& cage, const CageEdgeGrid& grid, const Vec2& a, const Vec2& b, double tol) {
  return grid.segmentDistance(a, b, 2.0 * tol) <= tol && cage.segmentCrosses(a, b);
}

}  // namespace

Region regionOf(SampleKind kind, bool closed) {
  if (!closed) return Region::Inside;  // open structures: one region, only crossings matter
  switch (kind) {
    case SampleKind::Control:
    case SampleKind::Edge: return Region::Boundary;
    case SampleKind::Exterior: return Region::Outside;
    default: return Region::Inside;
  }
}

/// The diffusion operator: K without the pairs whose segment crosses the cage, and directed so
/// heat never goes from the outside back in: samples inside or on the cage take heat only through
/// segments inside (or along) the cage; exterior samples take it from exterior and on-cage samples.
/// Without this, heat could leave the shape at an on-cage sample, cross a notch outside and enter
/// again at the other wall. Restricted to inside/on-cage rows (or to exterior rows) the operator is
/// symmetric: crossing tests use the ordered pair (min, max).
SparseRowMatrix diffusionOperator(const SampleSet& S, const Cage& cage, const SparseMatrix& K) {
  const Points& X = S.X;
  const Index n = X.rows();
  const Vec2 lo = X.colwise().minCoeff().transpose().cwiseMin(cage.C.colwise().minCoeff().transpose());
  const Vec2 hi = X.colwise().maxCoeff().transpose().cwiseMax(cage.C.colwise().maxCoeff().transpose());
  double reach = 0.0;  // longest kernel pair: a segment's bounding box then meets ≤ 2×2 cells
  for (Index c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it)
      reach = std::max(reach, (X.row(it.row()) - X.row(c)).cwiseAbs().maxCoeff());
  const double extent = std::max(1e-300, (hi - lo).norm()), tol = 1e-9 * extent;
  const CageEdgeGrid grid(cage, std::max(reach, 1e-6 * extent));
  const bool closed = hasInterior(cage);  // open sticks alone: one region
  const CageQueries queries(cage);

  std::vector<detail::SparseList> rows(static_cast<std::size_t>(n));
  parallelFor(n, [&](Index i) {
    auto& row = rows[static_cast<std::size_t>(i)];
    const Region ri = regionOf(S.kind[static_cast<std::size_t>(i)], closed);
    for (SparseMatrix::InnerIterator it(K, i); it; ++it) {  // K symmetric: column i = row i
      const Index j = it.row();
      if (j != i) {
        const Region rj = regionOf(S.kind[static_cast<std::size_t>(j)], closed);
        const Region lower = std::min(ri, rj), upper = std::max(ri, rj);
        if (lower == Region::Inside && upper == Region::Outside) continue;  // must cross the cage
        // The side the segment runs on; for two on-cage samples, its midpoint decides.
        Region side = lower == Region::Inside ? Region::Inside : (upper == Region::Outside ? Region::Outside : Region::Boundary);
        const Vec2 a = X.row(std::min(i, j)).transpose(), b = X.row(std::max(i, j)).transpose();
        if (side == Region::Boundary) {
          const Vec2 mid = 0.5 * (a + b);
          if (queries.distance(mid) > 1e-9 * (b - a).norm())
            side = queries.inside(mid) ? Region::Inside : Region::Outside;
        }
        if (ri != Region::Outside && side == Region::Outside) continue;
        if (ri == Region::Outside && side == Region::Inside) continue;
        if (crossesCage(queries, grid, a, b, tol)) continue;
      }
      row.emplace_back(j, it.value());
    }
  });
  // Each row is in increasing column order, as K's columns are.
  return detail::compressLists<SparseRowMatrix>(n, n, std::move(rows));
}

/// Unknown samples from which some known sample can be reached through the operator's rows.
std::vector<char> reachableFromKnown(const SparseRowMatrix& R, const std::vector<Index>& unknown,
                                     const std::vector<char>& isUnknown) {
  const Index n = R.rows();
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  std::vector<Index> stack;
  for (Index i : unknown)
    for (SparseRowMatrix::InnerIterator it(R, i); it; ++it)
      if (!isUnknown[static_cast<std::size_t>(it.col())]) {
        seen[static_cast<std::size_t>(i)] = 1;
        stack.push_back(i);
        break;
      }
  // Within one stage the operator is symmetric, so following rows outwards finds the component.
  while (!stack.empty()) {
    const Index i = stack.back();
    stack.pop_back();
    for (SparseRowMatrix::InnerIterator it(R, i); it; ++it) {
      const auto j = static_cast<std::size_t>(it.col());
      if (isUnknown[j] && !seen[j]) {
        seen[j] = 1;
        stack.push_back(it.col());
      }
    }
  }
  return seen;
}

}  // namespace kc::detail
