#pragma once
/// A coordinate field on a triangle mesh: per-vertex weights W (#V×m), barycentric (linear)
/// interpolation inside each triangle, undefined outside the mesh (weights 0 there). Point
/// location goes through a uniform grid over the triangles. Used by mesh backends (LBC) and by
/// tests that build a field by hand. Nodes are the vertices; Coef = W.

#include "kc/core/field/field.h"

namespace kc {

class MeshField final : public CoordinateField {
 public:
  MeshField() = default;
  /// V #V×2 vertex positions, T triangles (vertex indices), W #V×m weights. Throws
  /// std::invalid_argument for non-finite values, wrong shapes, indices out of range or a
  /// triangle of zero area.
  MeshField(Points V, Triangles T, Weights W);

  Index controls() const override { return m_W.cols(); }
  Index nodes() const override { return m_V.rows(); }
  bool ready() const override { return !m_T.empty() && m_W.size() > 0; }

  /// Row p = barycentric coordinates (λ_a, λ_b, λ_c) of p in its triangle (a, b, c), by
  /// increasing vertex index; empty when p is outside the mesh.
  SparseRowMatrix evaluationOperator(const Points& P) const override;
  /// Rows p = ∂λ/∂x, ∂λ/∂y of the triangle containing p, constant per triangle:
  /// ∇λ_a = (b_y − c_y, c_x − b_x)/(2A) with 2A = (b − a)×(c − a), cyclically (empty rows outside).
  void gradientOperators(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const override;
  RowMatrix coefficientColumns(std::span<const Index> columns = {}) const override;
  FieldDomain domain() const override { return FieldDomain::Mesh; }
  std::string_view kind() const override { return "mesh"; }
  bool contains(const Vec2& p) const override { return locate(p) >= 0; }
  /// Copies columns `columns` (all when empty) of the vertex weights W (#V×m).
  void update(const Weights& W, std::span<const Index> columns = {}) override;

  /// The triangle containing p (on a shared edge: the one where p is deepest inside), or −1.
  /// bary, when given, receives p's barycentric coordinates in it.
  Index locate(const Vec2& p, Eigen::Vector3d* bary = nullptr) const;

  const Points& vertices() const { return m_V; }
  const Triangles& triangles() const { return m_T; }
  const Weights& vertexWeights() const { return m_W; }

 private:
  Eigen::Vector3d barycentric(Index t, const Vec2& p) const;

  Points m_V;
  Triangles m_T;
  Weights m_W;
  // Uniform grid over the triangles' bounding boxes: cell → triangles (CSR).
  double m_x0 = 0.0, m_y0 = 0.0, m_cell = 1.0;
  int m_nx = 0, m_ny = 0;
  std::vector<int> m_start, m_items;
};

}  // namespace kc
