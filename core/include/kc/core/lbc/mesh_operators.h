#pragma once
/// Piecewise-linear finite elements on a triangle mesh: per-triangle areas and gradients of the
/// hat functions, the stiffness (cotangent) matrix and the lumped mass matrix.

#include <array>

#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc {

/// Per-triangle data of a P1 mesh: area a_s and ∇λ_v for its three corners (constant on s).
struct TriangleGradients {
  std::vector<double> area;                     ///< #T areas (positive).
  std::vector<std::array<Vec2, 3>> gradient;    ///< #T × 3: ∇λ of corner 0, 1, 2.
  std::vector<double> vertexMass;               ///< #V lumped masses m_v = Σ_{s∋v} a_s/3.
};

/// Areas, hat-function gradients ∇λ_a = R(c − b)/(2A_signed) (R = rotation by −90°) and lumped
/// masses. Throws std::invalid_argument for a triangle of zero area or an index out of range.
TriangleGradients triangleGradients(const Points& V, const Triangles& T);

/// Stiffness matrix L (#V×#V, symmetric positive semidefinite): L_uv = Σ_s a_s ∇λ_u·∇λ_v, the
/// cotangent Laplacian (½(cot α + cot β) off the diagonal, negated), so ∫|∇f|² = fᵀLf.
SparseMatrix stiffnessMatrix(const Triangles& T, const TriangleGradients& g, Index vertices);

/// Lumped mass matrix diag(m_v).
SparseMatrix massMatrix(const TriangleGradients& g);

}  // namespace kc
