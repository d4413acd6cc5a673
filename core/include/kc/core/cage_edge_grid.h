#pragma once
/// The one spatial index over a cage's edges: edges bucketed in a uniform grid over the cage's
/// bounding box, so "how far is the cage from this point", "does this short segment come close to
/// the cage" cost O(1) per query (for queries about one cell in size) instead of O(#edges).
/// Used by the blue-noise sampler (clearance of moves), the boundary sampler (dropping points near
/// the cage) and the heat-diffusion operator (which kernel pairs may cross the cage).

#include <array>
#include <cstddef>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc {

class CageEdgeGrid {
 public:
  /// Buckets the edges of cageEdges(cage) in square cells of side about `cell` (> 0; e.g. the
  /// query radius). The grid never has more than 1024 cells a side, whatever `cell` is: queries
  /// stay exact, only slower for a cell far below the cage's size.
  CageEdgeGrid(const Cage& cage, double cell);

  /// Calls f(edge, a, b) for every edge (index into cageEdges(cage), end points a, b) that may come
  /// within the box [lo, hi]: a superset of the edges meeting the box, each reported once per cell
  /// it is bucketed in (so possibly more than once). Deterministic order.
  template <class F>
  void forEachEdgeNear(const Vec2& lo, const Vec2& hi, F&& f) const {
    const double pad = 0.25 * m_cell;  // edges are registered at points every half cell
    const double x0 = lo.x() - pad, y0 = lo.y() - pad, x1 = hi.x() + pad, y1 = hi.y() + pad;
    if (m_seg.empty() || x1 < m_x0 || y1 < m_y0 || x0 > m_x0 + m_nx * m_cell || y0 > m_y0 + m_ny * m_cell) return;
    const int cx0 = cellX(x0), cx1 = cellX(x1), cy0 = cellY(y0), cy1 = cellY(y1);
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx) {
        const std::size_t c = static_cast<std::size_t>(cy) * static_cast<std::size_t>(m_nx) + static_cast<std::size_t>(cx);
        for (int k = m_start[c]; k < m_start[c + 1]; ++k) {
          const int e = m_items[static_cast<std::size_t>(k)];
          const auto& s = m_seg[static_cast<std::size_t>(e)];
          f(e, s[0], s[1]);
        }
      }
  }

  /// Distance from x to the nearest cage edge when it is below maxDistance, else maxDistance.
  double distance(const Vec2& x, double maxDistance) const;
  /// Distance from the segment a–b to the nearest cage edge when it is below maxDistance, else
  /// maxDistance (0 when the segment crosses an edge).
  double segmentDistance(const Vec2& a, const Vec2& b, double maxDistance) const;
  /// True when every point of segment a–b is at least `clearance` away from every cage edge.
  bool segmentClear(const Vec2& a, const Vec2& b, double clearance) const;

 private:
  int cellX(double x) const;
  int cellY(double y) const;

  std::vector<std::array<Vec2, 2>> m_seg;  // edge end points, in cageEdges order
  double m_cell = 1.0, m_x0 = 0.0, m_y0 = 0.0;
  int m_nx = 0, m_ny = 0;
  std::vector<int> m_start;  // cell → first slot in m_items (size cells + 1)
  std::vector<int> m_items;  // edge indices per cell
};

}  // namespace kc
