#include "cage_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kc/sampling/boundary.h"

namespace kc::sampling::detail {

CageLocator::CageLocator(const Cage& cage, double cell) {
  for (const auto& [a, b] : cageEdges(cage)) m_seg.push_back({Vec2(cage.C.row(a)), Vec2(cage.C.row(b))});
  const double x0 = cage.C.col(0).minCoeff(), x1 = cage.C.col(0).maxCoeff();
  const double y0 = cage.C.col(1).minCoeff(), y1 = cage.C.col(1).maxCoeff();
  // At most ~4096² cells whatever the cell size.
  m_cell = std::max({cell, (x1 - x0) / 4096.0, (y1 - y0) / 4096.0, 1e-12});
  m_x0 = x0;
  m_y0 = y0;
  m_nx = static_cast<int>(std::floor((x1 - x0) / m_cell)) + 1;
  m_ny = static_cast<int>(std::floor((y1 - y0) / m_cell)) + 1;
  // Each edge is registered in the cells of points taken every half cell along it, so any
  // point of the edge lies within a quarter cell of a registered cell's point.
  std::vector<std::pair<int, int>> entries;  // (cell, edge)
  for (int e = 0; e < static_cast<int>(m_seg.size()); ++e) {
    const Vec2 A = m_seg[static_cast<std::size_t>(e)][0], B = m_seg[static_cast<std::size_t>(e)][1];
    const int steps = static_cast<int>(std::ceil((B - A).norm() / (0.5 * m_cell))) + 1;
    int last = -1;
    for (int k = 0; k <= steps; ++k) {
      const Vec2 p = A + (B - A) * (static_cast<double>(k) / steps);
      const int c = cellY(p.y()) * m_nx + cellX(p.x());
      if (c != last) entries.emplace_back(c, e);
      last = c;
    }
  }
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  const std::size_t cells = static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny);
  m_start.assign(cells + 1, 0);
  for (const auto& [c, e] : entries) ++m_start[static_cast<std::size_t>(c) + 1];
  for (std::size_t c = 0; c < cells; ++c) m_start[c + 1] += m_start[c];
  m_items.resize(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) m_items[k] = entries[k].second;
}

int CageLocator::cellX(double x) const {
  return static_cast<int>(std::clamp(std::floor((x - m_x0) / m_cell), 0.0, static_cast<double>(m_nx - 1)));
}

int CageLocator::cellY(double y) const {
  return static_cast<int>(std::clamp(std::floor((y - m_y0) / m_cell), 0.0, static_cast<double>(m_ny - 1)));
}

template <class F>
void CageLocator::forEachEdgeNear(double xmin, double ymin, double xmax, double ymax, F&& f) const {
  const double pad = 0.25 * m_cell;
  xmin -= pad, ymin -= pad, xmax += pad, ymax += pad;
  if (xmax < m_x0 || ymax < m_y0 || xmin > m_x0 + m_nx * m_cell || ymin > m_y0 + m_ny * m_cell) return;
  const int cx0 = cellX(xmin), cx1 = cellX(xmax), cy0 = cellY(ymin), cy1 = cellY(ymax);
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx) {
      const std::size_t c = static_cast<std::size_t>(cy) * static_cast<std::size_t>(m_nx) + static_cast<std::size_t>(cx);
      for (int k = m_start[c]; k < m_start[c + 1]; ++k) f(m_seg[static_cast<std::size_t>(m_items[static_cast<std::size_t>(k)])]);
    }
}

double CageLocator::distance(const Vec2& x, double maxDistance) const {
  double best = maxDistance;
  forEachEdgeNear(x.x() - maxDistance, x.y() - maxDistance, x.x() + maxDistance, x.y() + maxDistance,
                  [&](const std::array<Vec2, 2>& s) { best = std::min(best, pointSegmentDistance(x, s[0], s[1])); });
  return best;
}

bool CageLocator::segmentClear(const Vec2& a, const Vec2& b, double clearance) const {
  bool clear = true;
  forEachEdgeNear(std::min(a.x(), b.x()) - clearance, std::min(a.y(), b.y()) - clearance,
                  std::max(a.x(), b.x()) + clearance, std::max(a.y(), b.y()) + clearance,
                  [&](const std::array<Vec2, 2>& s) {
                    if (clear && segmentSegmentDistance(a, b, s[0], s[1]) < clearance) clear = false;
                  });
  return clear;
}

}  // namespace kc::sampling::detail
