#include "kc/core/field/mesh_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "kc/core/parallel.h"
#include "../sparse_lists.h"

namespace kc {
namespace {

double cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

/// Three (vertex, value) pairs sorted by vertex.
std::vector<std::pair<int, double>> sortedTriple(const std::array<int, 3>& t, const Eigen::Vector3d& v) {
  std::vector<std::pair<int, double>> r = {{t[0], v(0)}, {t[1], v(1)}, {t[2], v(2)}};
  std::sort(r.begin(), r.end());
  return r;
}

}  // namespace

MeshField::MeshField(Points V, Triangles T, Weights W) : m_V(std::move(V)), m_T(std::move(T)), m_W(std::move(W)) {
  const Index nv = m_V.rows();
  if (nv == 0 || m_T.empty()) throw std::invalid_argument("mesh field: the mesh has no vertices or no triangles");
  if (!m_V.allFinite()) throw std::invalid_argument("mesh field: vertex positions must be finite");
  if (m_W.rows() != nv)
    throw std::invalid_argument("mesh field: weights have " + std::to_string(m_W.rows()) + " rows but there are " +
                                std::to_string(nv) + " vertices");
  if (m_W.cols() == 0 || !m_W.allFinite()) throw std::invalid_argument("mesh field: weights must be finite, at least one column");
  const double x0 = m_V.col(0).minCoeff(), x1 = m_V.col(0).maxCoeff();
  const double y0 = m_V.col(1).minCoeff(), y1 = m_V.col(1).maxCoeff();
  const double extent = std::max({x1 - x0, y1 - y0, 1e-300});
  for (std::size_t t = 0; t < m_T.size(); ++t) {
    for (int k : m_T[t])
      if (k < 0 || k >= nv)
        throw std::invalid_argument("mesh field: triangle " + std::to_string(t) + " has vertex " + std::to_string(k) +
                                    " out of range 0.." + std::to_string(nv - 1));
    const Vec2 a = m_V.row(m_T[t][0]).transpose(), b = m_V.row(m_T[t][1]).transpose(), c = m_V.row(m_T[t][2]).transpose();
    if (!(std::abs(cross(b - a, c - a)) > 1e-14 * extent * extent))
      throw std::invalid_argument("mesh field: triangle " + std::to_string(t) + " has zero area");
  }
  // Grid: about one triangle per cell on average, each triangle listed in the cells its bounding box meets.
  m_x0 = x0;
  m_y0 = y0;
  m_cell = std::max(extent / std::max(1.0, std::sqrt(static_cast<double>(m_T.size()))), 1e-12 * extent);
  m_nx = static_cast<int>(std::floor((x1 - x0) / m_cell)) + 1;
  m_ny = static_cast<int>(std::floor((y1 - y0) / m_cell)) + 1;
  auto cellRange = [&](std::size_t t, int& cx0, int& cx1, int& cy0, int& cy1) {
    double bx0 = 1e300, bx1 = -1e300, by0 = 1e300, by1 = -1e300;
    for (int k : m_T[t]) {
      bx0 = std::min(bx0, m_V(k, 0));
      bx1 = std::max(bx1, m_V(k, 0));
      by0 = std::min(by0, m_V(k, 1));
      by1 = std::max(by1, m_V(k, 1));
    }
    auto cell = [&](double v, double o, int n) { return std::clamp(static_cast<int>(std::floor((v - o) / m_cell)), 0, n - 1); };
    cx0 = cell(bx0, m_x0, m_nx);
    cx1 = cell(bx1, m_x0, m_nx);
    cy0 = cell(by0, m_y0, m_ny);
    cy1 = cell(by1, m_y0, m_ny);
  };
  const std::size_t cells = static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny);
  m_start.assign(cells + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill(m_start.begin(), m_start.end() - 1);
    for (std::size_t t = 0; t < m_T.size(); ++t) {
      int cx0, cx1, cy0, cy1;
      cellRange(t, cx0, cx1, cy0, cy1);
      for (int cy = cy0; cy <= cy1; ++cy)
        for (int cx = cx0; cx <= cx1; ++cx) {
          const std::size_t c = static_cast<std::size_t>(cy) * m_nx + cx;
          if (pass == 0)
            ++m_start[c + 1];
          else
            m_items[static_cast<std::size_t>(fill[c]++)] = static_cast<int>(t);
        }
    }
    if (pass == 0) {
      for (std::size_t c = 0; c < cells; ++c) m_start[c + 1] += m_start[c];
      m_items.assign(static_cast<std::size_t>(m_start[cells]), 0);
    }
  }
}

Eigen::Vector3d MeshField::barycentric(Index t, const Vec2& p) const {
  const auto& tri = m_T[static_cast<std::size_t>(t)];
  const Vec2 a = m_V.row(tri[0]).transpose(), b = m_V.row(tri[1]).transpose(), c = m_V.row(tri[2]).transpose();
  const double area2 = cross(b - a, c - a);
  const double la = cross(c - b, p - b) / area2, lb = cross(a - c, p - c) / area2;
  return {la, lb, 1.0 - la - lb};
}

Index MeshField::locate(const Vec2& p, Eigen::Vector3d* bary) const {
  if (m_T.empty() || !p.allFinite()) return -1;
  const double fx = std::floor((p.x() - m_x0) / m_cell), fy = std::floor((p.y() - m_y0) / m_cell);
  // Beyond one cell of the grid nothing can contain p; within it the barycentric test decides.
  if (fx < -1 || fy < -1 || fx > m_nx || fy > m_ny) return -1;
  const int cx = std::clamp(static_cast<int>(fx), 0, m_nx - 1), cy = std::clamp(static_cast<int>(fy), 0, m_ny - 1);
  const std::size_t c = static_cast<std::size_t>(cy) * m_nx + cx;
  // Tolerance for points on edges and vertices (round-off in the barycentric coordinates).
  constexpr double kEdgeTolerance = 1e-12;
  Index best = -1;
  double bestMin = -kEdgeTolerance;
  Eigen::Vector3d bestBary = Eigen::Vector3d::Zero();
  for (int k = m_start[c]; k < m_start[c + 1]; ++k) {
    const Index t = m_items[static_cast<std::size_t>(k)];
    const Eigen::Vector3d l = barycentric(t, p);
    if (l.minCoeff() >= bestMin && (best < 0 || l.minCoeff() > bestMin)) {
      best = t;
      bestMin = l.minCoeff();
      bestBary = l;
    }
  }
  if (bary && best >= 0) *bary = bestBary;
  return best;
}

SparseRowMatrix MeshField::evaluationOperator(const Points& P) const {
  if (!P.allFinite()) throw std::invalid_argument("mesh field: query points must be finite");
  std::vector<std::vector<std::pair<int, double>>> rows(static_cast<std::size_t>(P.rows()));
  parallelFor(P.rows(), [&](Index p) {
    Eigen::Vector3d l;
    const Index t = locate(P.row(p).transpose(), &l);
    if (t >= 0) rows[static_cast<std::size_t>(p)] = sortedTriple(m_T[static_cast<std::size_t>(t)], l);
  });
  return detail::compressLists<SparseRowMatrix>(Index(rows.size()), nodes(), std::move(rows));
}

void MeshField::gradientOperators(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const {
  if (!P.allFinite()) throw std::invalid_argument("mesh field: query points must be finite");
  std::vector<std::vector<std::pair<int, double>>> gx(static_cast<std::size_t>(P.rows())), gy(gx.size());
  parallelFor(P.rows(), [&](Index p) {
    const Index t = locate(P.row(p).transpose());
    if (t < 0) return;
    const auto& tri = m_T[static_cast<std::size_t>(t)];
    const Vec2 v[3] = {m_V.row(tri[0]).transpose(), m_V.row(tri[1]).transpose(), m_V.row(tri[2]).transpose()};
    const double area2 = cross(v[1] - v[0], v[2] - v[0]);
    Eigen::Vector3d dx, dy;
    for (int i = 0; i < 3; ++i) {
      const Vec2& b = v[(i + 1) % 3];
      const Vec2& c = v[(i + 2) % 3];
      dx(i) = (b.y() - c.y()) / area2;
      dy(i) = (c.x() - b.x()) / area2;
    }
    gx[static_cast<std::size_t>(p)] = sortedTriple(tri, dx);
    gy[static_cast<std::size_t>(p)] = sortedTriple(tri, dy);
  });
  Ex = detail::compressLists<SparseRowMatrix>(Index(gx.size()), nodes(), std::move(gx));
  Ey = detail::compressLists<SparseRowMatrix>(Index(gy.size()), nodes(), std::move(gy));
}

RowMatrix MeshField::coefficientColumns(std::span<const Index> columns) const {
  const std::vector<Index> cols = detail::fieldColumns(columns, controls());
  RowMatrix C(m_W.rows(), static_cast<Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) C.col(static_cast<Index>(k)) = m_W.col(cols[k]);
  return C;
}

void MeshField::update(const Weights& W, std::span<const Index> columns) {
  if (W.rows() != m_V.rows()) throw std::invalid_argument("mesh field: W must have one row per vertex");
  if (!W.allFinite()) throw std::invalid_argument("mesh field: weights must be finite");
  if (columns.empty() || W.cols() != m_W.cols()) {
    m_W = W;
    return;
  }
  for (const Index c : detail::fieldColumns(columns, m_W.cols())) m_W.col(c) = W.col(c);
}

}  // namespace kc
