#include "kc/core/lbc/mesh_operators.h"

#include <cmath>
#include <stdexcept>
#include <string>


namespace kc {

TriangleGradients triangleGradients(const Points& V, const Triangles& T) {
  TriangleGradients g;
  const Index nt = Index(T.size());
  g.area.resize(T.size());
  g.gradient.resize(T.size());
  g.vertexMass.assign(std::size_t(V.rows()), 0.0);
  for (Index s = 0; s < nt; ++s) {
    const auto& t = T[std::size_t(s)];
    for (int k : t)
      if (k < 0 || k >= V.rows()) throw std::invalid_argument("mesh: triangle " + std::to_string(s) + " has a vertex out of range");
    const Vec2 a = V.row(t[0]), b = V.row(t[1]), c = V.row(t[2]);
    const double twice = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (!(std::abs(twice) > 0.0)) throw std::invalid_argument("mesh: triangle " + std::to_string(s) + " has zero area");
    // ∇λ_a is perpendicular to the opposite edge b→c: (b_y − c_y, c_x − b_x)/(2A), cyclically.
    const Vec2 p[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Vec2& u = p[(k + 1) % 3];
      const Vec2& w = p[(k + 2) % 3];
      g.gradient[std::size_t(s)][std::size_t(k)] = Vec2(u.y() - w.y(), w.x() - u.x()) / twice;
    }
    g.area[std::size_t(s)] = 0.5 * std::abs(twice);
    for (int k : t) g.vertexMass[std::size_t(k)] += g.area[std::size_t(s)] / 3.0;
  }
  return g;
}

SparseMatrix stiffnessMatrix(const Triangles& T, const TriangleGradients& g, Index vertices) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * T.size());
  for (std::size_t s = 0; s < T.size(); ++s)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        trip.emplace_back(T[s][std::size_t(a)], T[s][std::size_t(b)],
                          g.area[s] * g.gradient[s][std::size_t(a)].dot(g.gradient[s][std::size_t(b)]));
  SparseMatrix L(vertices, vertices);
  L.setFromTriplets(trip.begin(), trip.end());
  return L;
}

SparseMatrix massMatrix(const TriangleGradients& g) {
  const Index n = Index(g.vertexMass.size());
  SparseMatrix M(n, n);
  M.reserve(Eigen::VectorXi::Constant(n, 1));
  for (Index v = 0; v < n; ++v) M.insert(v, v) = g.vertexMass[std::size_t(v)];
  M.makeCompressed();
  return M;
}

}  // namespace kc
