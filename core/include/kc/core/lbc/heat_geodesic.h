#pragma once
/// Geodesic distances inside a triangle mesh by the heat method (Crane, Weischedel and
/// Wardetzky 2013): one heat step, the normalized gradient, a Poisson solve.

#include <span>

#include "kc/core/lbc/mesh_operators.h"

namespace kc {

struct HeatGeodesicReport {
  bool ok = true;           ///< Both factorizations succeeded.
  double seconds = 0.0;
};

/// Distances from each source vertex to every vertex: #V×k (column j = distance to sources[j]).
/// Heat method with Neumann boundary: (M + tL) u = e_src with t = (mean edge length)², the unit
/// field X = −∇u/|∇u| per triangle, then L φ = Gᵀ·A·X (the integrated divergence) solved with
/// L + εM (ε = 1e-9/diameter², removes L's constant null space), φ shifted so that φ(src) = 0
/// and clamped at 0. Two factorizations for all k sources. V #V×2, T the mesh, L its stiffness
/// matrix and g its triangle gradients (mesh_operators.h).
Eigen::MatrixXd heatGeodesics(const Points& V, const Triangles& T, const TriangleGradients& g, const SparseMatrix& L,
                              std::span<const Index> sources, HeatGeodesicReport* report = nullptr);

}  // namespace kc
