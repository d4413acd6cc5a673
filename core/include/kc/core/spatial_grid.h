#pragma once
/// Uniform grid (spatial hash) over a point set: neighbour queries in O(1) per neighbour, so
/// assembling a cut-off kernel or relaxing a sampling costs O(n), never O(n²).

#include <vector>

#include "kc/core/types.h"

namespace kc {

class SpatialGrid {
 public:
  SpatialGrid() = default;
  /// Buckets (a copy of) the rows of X into square cells of side `cell` (> 0).
  SpatialGrid(const Points& X, double cell) { build(X, cell); }
  void build(const Points& X, double cell);

  /// Calls f(j, squaredDistance) for every point j with |X_j − x| ≤ radius, in increasing j
  /// within each cell and cells in a fixed order (deterministic).
  template <class F>
  void forEachWithin(const Vec2& x, double radius, F&& f) const {
    if (m_index.empty()) return;
    const double r2 = radius * radius;
    const int cx0 = cellX(x.x() - radius), cx1 = cellX(x.x() + radius);
    const int cy0 = cellY(x.y() - radius), cy1 = cellY(x.y() + radius);
    for (int cy = cy0; cy <= cy1; ++cy) {
      for (int cx = cx0; cx <= cx1; ++cx) {
        const int c = cy * m_nx + cx;
        for (int k = m_start[c]; k < m_start[c + 1]; ++k) {
          const double dx = m_xy[2 * k] - x.x(), dy = m_xy[2 * k + 1] - x.y();
          const double d2 = dx * dx + dy * dy;
          if (d2 <= r2) f(m_index[k], d2);
        }
      }
    }
  }

 private:
  int cellX(double x) const;
  int cellY(double y) const;

  double m_cell = 1.0;
  double m_x0 = 0.0, m_y0 = 0.0;
  int m_nx = 0, m_ny = 0;
  std::vector<int> m_start;   // cell → first slot in m_index (size cells + 1)
  std::vector<Index> m_index; // point indices sorted by cell (stable within a cell)
  std::vector<double> m_xy;    // their coordinates, in the same order
};

}  // namespace kc
