#include "kc/core/cage_edge_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace kc {

CageEdgeGrid::CageEdgeGrid(const Cage& cage, double cell) {
  for (const auto& [a, b] : cageEdges(cage)) m_seg.push_back({Vec2(cage.C.row(a)), Vec2(cage.C.row(b))});
  if (m_seg.empty()) return;
  const double x0 = cage.C.col(0).minCoeff(), x1 = cage.C.col(0).maxCoeff();
  const double y0 = cage.C.col(1).minCoeff(), y1 = cage.C.col(1).maxCoeff();
  m_cell = std::max({cell, (x1 - x0) / 1024.0, (y1 - y0) / 1024.0, 1e-12});
  m_x0 = x0;
  m_y0 = y0;
  m_nx = static_cast<int>(std::floor((x1 - x0) / m_cell)) + 1;
  m_ny = static_cast<int>(std::floor((y1 - y0) / m_cell)) + 1;
  // Each edge is registered in the cells of points taken every half cell along it, so any point of
  // the edge lies within a quarter cell of a registered cell (forEachEdgeNear pads by that much).
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

int CageEdgeGrid::cellX(double x) const {
  return static_cast<int>(std::clamp(std::floor((x - m_x0) / m_cell), 0.0, static_cast<double>(m_nx - 1)));
}

int CageEdgeGrid::cellY(double y) const {
  return static_cast<int>(std::clamp(std::floor((y - m_y0) / m_cell), 0.0, static_cast<double>(m_ny - 1)));
}

double CageEdgeGrid::distance(const Vec2& x, double maxDistance) const {
  double best = maxDistance;
  const Vec2 r = Vec2::Constant(maxDistance);
  forEachEdgeNear(x - r, x + r, [&](int, const Vec2& a, const Vec2& b) { best = std::min(best, pointSegmentDistance(x, a, b)); });
  return best;
}

double CageEdgeGrid::segmentDistance(const Vec2& a, const Vec2& b, double maxDistance) const {
  double best = maxDistance;
  const Vec2 r = Vec2::Constant(maxDistance);
  forEachEdgeNear(a.cwiseMin(b) - r, a.cwiseMax(b) + r, [&](int, const Vec2& p, const Vec2& q) {
    if (best > 0.0) best = std::min(best, segmentSegmentDistance(a, b, p, q));
  });
  return best;
}

bool CageEdgeGrid::segmentClear(const Vec2& a, const Vec2& b, double clearance) const {
  bool clear = true;  // stops measuring at the first edge too close (the sampler's hot path)
  const Vec2 r = Vec2::Constant(clearance);
  forEachEdgeNear(a.cwiseMin(b) - r, a.cwiseMax(b) + r, [&](int, const Vec2& p, const Vec2& q) {
    if (clear && segmentSegmentDistance(a, b, p, q) < clearance) clear = false;
  });
  return clear;
}

}  // namespace kc
