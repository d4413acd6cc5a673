#include "kc/core/lbc/heat_geodesic.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "../sparse_cholesky.h"
#include "kc/core/parallel.h"

namespace kc {

Eigen::MatrixXd heatGeodesics(const Points& V, const Triangles& T, const TriangleGradients& g, const SparseMatrix& L,
                              std::span<const Index> sources, HeatGeodesicReport* report) {
  const auto start = std::chrono::steady_clock::now();
  const Index nv = V.rows(), k = Index(sources.size());
  HeatGeodesicReport rep;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(nv, k);
  if (k == 0 || T.empty()) {
    if (report) *report = rep;
    return D;
  }
  double edgeSum = 0.0;
  for (const auto& t : T)
    for (int a = 0; a < 3; ++a) edgeSum += (V.row(t[std::size_t(a)]) - V.row(t[std::size_t((a + 1) % 3)])).norm();
  const double h = edgeSum / double(3 * T.size());
  const SparseMatrix M = massMatrix(g);

  // 1. Heat step (M + tL) u = e_src, t = h².
  detail::SupernodalCholesky heat;
  heat.compute(SparseMatrix(M + (h * h) * L));
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(nv, k);
  for (Index j = 0; j < k; ++j) U(sources[std::size_t(j)], j) = 1.0;
  rep.ok = heat.info() == Eigen::Success;
  if (rep.ok) U = heat.solve(U);

  // 2. X = −∇u/|∇u| per triangle, 3. integrated divergence b_v = Σ_s a_s ∇λ_v·X_s (per column).
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(nv, k);
  parallelFor(k, [&](Index j) {
    for (std::size_t s = 0; s < T.size(); ++s) {
      const auto& t = T[s];
      const auto& gr = g.gradient[s];
      Vec2 grad = gr[0] * U(t[0], j) + gr[1] * U(t[1], j) + gr[2] * U(t[2], j);
      const double n = grad.norm();
      if (!(n > 0.0)) continue;
      const Vec2 X = -grad / n;
      for (int a = 0; a < 3; ++a) B(t[std::size_t(a)], j) += g.area[s] * gr[std::size_t(a)].dot(X);
    }
  }, 1);

  // 4. Poisson solve (L + εM) φ = b; shift φ(src) to 0 and clamp below at 0.
  const double diameter = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  detail::SupernodalCholesky poisson;
  poisson.compute(SparseMatrix(L + (1e-9 / (diameter * diameter)) * M));
  rep.ok = rep.ok && poisson.info() == Eigen::Success;
  if (rep.ok) D = poisson.solve(B);
  parallelFor(k, [&](Index j) {
    const double base = D(sources[std::size_t(j)], j);
    for (Index v = 0; v < nv; ++v) D(v, j) = std::max(0.0, D(v, j) - base);
  }, 1);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (report) *report = rep;
  return D;
}

}  // namespace kc
