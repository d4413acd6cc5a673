#include "kc/core/spatial_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kc {

void SpatialGrid::build(const Points& X, double cell) {
  if (!(cell > 0.0) || !std::isfinite(cell)) throw std::invalid_argument("SpatialGrid: cell size must be positive");
  m_cell = cell;
  m_index.clear();
  m_xy.clear();
  const Index n = X.rows();
  if (n == 0) {
    m_nx = m_ny = 0;
    m_start.assign(1, 0);
    return;
  }
  const double x0 = X.col(0).minCoeff(), x1 = X.col(0).maxCoeff();
  const double y0 = X.col(1).minCoeff(), y1 = X.col(1).maxCoeff();
  if (!std::isfinite(x0 + x1 + y0 + y1)) throw std::invalid_argument("SpatialGrid: non-finite point");
  // Keep the cell count bounded (≤ ~4 cells per point) however small the cell.
  const double extent = std::max(x1 - x0, y1 - y0);
  const double minCell = extent / std::max(1.0, std::sqrt(4.0 * static_cast<double>(n)) + 1.0);
  m_cell = std::max(cell, minCell);
  m_x0 = x0;
  m_y0 = y0;
  m_nx = static_cast<int>(std::floor((x1 - x0) / m_cell)) + 1;
  m_ny = static_cast<int>(std::floor((y1 - y0) / m_cell)) + 1;
  const std::size_t cells = static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny);
  std::vector<int> cellOf(static_cast<std::size_t>(n));
  m_start.assign(cells + 1, 0);
  for (Index i = 0; i < n; ++i) {
    const int c = cellY(X(i, 1)) * m_nx + cellX(X(i, 0));
    cellOf[static_cast<std::size_t>(i)] = c;
    ++m_start[static_cast<std::size_t>(c) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) m_start[c + 1] += m_start[c];
  std::vector<int> fill(m_start.begin(), m_start.end() - 1);
  m_index.resize(static_cast<std::size_t>(n));
  m_xy.resize(2 * static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    const int k = fill[static_cast<std::size_t>(cellOf[static_cast<std::size_t>(i)])]++;
    m_index[static_cast<std::size_t>(k)] = i;
    m_xy[2 * static_cast<std::size_t>(k)] = X(i, 0);
    m_xy[2 * static_cast<std::size_t>(k) + 1] = X(i, 1);
  }
}

int SpatialGrid::cellX(double x) const {
  const double c = std::floor((x - m_x0) / m_cell);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(m_nx - 1)));
}

int SpatialGrid::cellY(double y) const {
  const double c = std::floor((y - m_y0) / m_cell);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(m_ny - 1)));
}

}  // namespace kc
