#include "kc/core/field/mesh_field.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "point_problems.h"

namespace kc {
namespace {

/// (n+1)² vertices on [0, n·h]², interior ones jittered, each square split into two triangles.
struct GridMesh {
  Points V;
  Triangles T;
};

GridMesh gridMesh(int n, double h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.3 * h, 0.3 * h);
  GridMesh g;
  g.V.resize((n + 1) * (n + 1), 2);
  for (int r = 0; r <= n; ++r)
    for (int c = 0; c <= n; ++c) {
      const bool border = r == 0 || c == 0 || r == n || c == n;
      g.V.row(r * (n + 1) + c) << c * h + (border ? 0.0 : u(rng)), r * h + (border ? 0.0 : u(rng));
    }
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const int a = r * (n + 1) + c, b = a + 1, d = a + n + 1, e = d + 1;
      g.T.push_back({a, b, e});
      g.T.push_back({a, e, d});
    }
  return g;
}

Points randomPoints(int count, double lo, double hi, unsigned seed) { return test::randomPointsIn(count, lo, hi, seed); }

/// Columns k of W are the linear functions a_k + b_k x + c_k y at the rows of V.
Weights linearData(const Points& V, const Eigen::Matrix<double, 3, 3>& abc) {
  Weights W(V.rows(), 3);
  for (Index i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k) W(i, k) = abc(0, k) + abc(1, k) * V(i, 0) + abc(2, k) * V(i, 1);
  return W;
}

/// The brute-force answer: does any triangle contain p (barycentrics ≥ −1e-12)?
bool insideAny(const GridMesh& g, const Vec2& p) {
  for (const auto& t : g.T) {
    const Vec2 a = g.V.row(t[0]).transpose(), b = g.V.row(t[1]).transpose(), c = g.V.row(t[2]).transpose();
    auto cr = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
    const double A = cr(b - a, c - a);
    const double la = cr(c - b, p - b) / A, lb = cr(a - c, p - c) / A, lc = 1 - la - lb;
    if (std::min({la, lb, lc}) >= -1e-12) return true;
  }
  return false;
}

TEST(MeshField, ExactOnLinearData) {
  const GridMesh g = gridMesh(9, 10.0, 1);
  Eigen::Matrix<double, 3, 3> abc;
  abc << 0.3, -1.0, 2.0, 0.01, 0.02, -0.005, -0.03, 0.004, 0.01;
  const MeshField f(g.V, g.T, linearData(g.V, abc));
  const Points P = randomPoints(500, 0.0, 90.0, 2);
  const Weights W = f.weightsAt(P);
  EXPECT_LE((W - linearData(P, abc)).cwiseAbs().maxCoeff(), 1e-12);
  // E(P)·Coef is the same thing, and the gradient of linear data is its slope everywhere.
  EXPECT_LE((Weights(f.evaluationOperator(P) * f.coefficients()) - W).cwiseAbs().maxCoeff(), 1e-13);
  Weights gx, gy;
  f.gradientsAt(P, gx, gy);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE((gx.col(k).array() - abc(1, k)).abs().maxCoeff(), 1e-12);
    EXPECT_LE((gy.col(k).array() - abc(2, k)).abs().maxCoeff(), 1e-12);
  }
}

TEST(MeshField, GradientsMatchFiniteDifferences) {
  const GridMesh g = gridMesh(7, 10.0, 3);
  const MeshField f(g.V, g.T, test::randomWeights(g.V.rows(), 2, 4));
  const Points P = randomPoints(300, 1.0, 69.0, 5);
  Weights gx, gy;
  f.gradientsAt(P, gx, gy);
  const double h = 1e-6;
  Index compared = 0;
  for (Index p = 0; p < P.rows(); ++p) {
    const Vec2 x = P.row(p).transpose();
    const Index t = f.locate(x);
    // Central differences are exact inside one triangle: skip points within h of an edge.
    if (f.locate(x + Vec2(h, 0)) != t || f.locate(x - Vec2(h, 0)) != t || f.locate(x + Vec2(0, h)) != t ||
        f.locate(x - Vec2(0, h)) != t)
      continue;
    Points Q(4, 2);
    Q << x.x() + h, x.y(), x.x() - h, x.y(), x.x(), x.y() + h, x.x(), x.y() - h;
    const Weights w = f.weightsAt(Q);
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(gx(p, k), (w(0, k) - w(1, k)) / (2 * h), 1e-6);
      EXPECT_NEAR(gy(p, k), (w(2, k) - w(3, k)) / (2 * h), 1e-6);
    }
    ++compared;
  }
  EXPECT_GT(compared, 250);
}

TEST(MeshField, PointLocationAgreesWithBruteForce) {
  const GridMesh g = gridMesh(12, 5.0, 6);
  const MeshField f(g.V, g.T, Weights::Ones(g.V.rows(), 1));
  Points P = randomPoints(2000, -10.0, 70.0, 7);
  // Vertices and edge midpoints: on the boundary between triangles.
  Points onEdges(static_cast<Index>(g.T.size()), 2);
  for (std::size_t t = 0; t < g.T.size(); ++t)
    onEdges.row(static_cast<Index>(t)) = 0.5 * (g.V.row(g.T[t][0]) + g.V.row(g.T[t][1]));
  Points all(P.rows() + onEdges.rows() + g.V.rows(), 2);
  all << P, onEdges, g.V;
  Index inside = 0;
  for (Index p = 0; p < all.rows(); ++p) {
    const Vec2 x = all.row(p).transpose();
    Eigen::Vector3d l;
    const Index t = f.locate(x, &l);
    ASSERT_EQ(t >= 0, insideAny(g, x)) << "point " << x.transpose();
    EXPECT_EQ(f.contains(x), t >= 0);
    if (t < 0) continue;
    ++inside;
    EXPECT_GE(l.minCoeff(), -1e-12);
    // The barycentrics reproduce the point.
    const auto& tri = g.T[static_cast<std::size_t>(t)];
    const Vec2 r = l(0) * g.V.row(tri[0]).transpose() + l(1) * g.V.row(tri[1]).transpose() + l(2) * g.V.row(tri[2]).transpose();
    EXPECT_LE((r - x).norm(), 1e-9);
  }
  EXPECT_GT(inside, 1000);
  EXPECT_LT(inside, all.rows());  // some points were outside
}

TEST(MeshField, OutsideTheMeshHasNoWeights) {
  const GridMesh g = gridMesh(3, 1.0, 8);
  const MeshField f(g.V, g.T, Weights::Ones(g.V.rows(), 2));
  Points P(2, 2);
  P << -0.5, 0.5, 1.5, 1.5;
  const SparseRowMatrix E = f.evaluationOperator(P);
  EXPECT_EQ(E.row(0).nonZeros(), 0);
  EXPECT_EQ(E.row(1).nonZeros(), 3);
  EXPECT_EQ(f.domain(), FieldDomain::Mesh);
  const Weights W = f.weightsAt(P);
  EXPECT_EQ(W(0, 0), 0.0);
  EXPECT_NEAR(W(1, 0), 1.0, 1e-14);
}

TEST(MeshField, UpdateReplacesOnlyTheGivenColumns) {
  const GridMesh g = gridMesh(3, 1.0, 9);
  MeshField f(g.V, g.T, Weights::Zero(g.V.rows(), 3));
  const std::vector<Index> cols = {1};
  f.update(Weights::Ones(g.V.rows(), 3), cols);
  EXPECT_EQ(f.vertexWeights().col(0).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(f.vertexWeights().col(1).minCoeff(), 1.0);
  EXPECT_EQ(f.vertexWeights().col(2).cwiseAbs().maxCoeff(), 0.0);
  const std::vector<Index> bad = {3};
  EXPECT_THROW(f.update(Weights::Ones(g.V.rows(), 3), bad), std::invalid_argument);
}

TEST(MeshField, RejectsBadMeshes) {
  Points V(3, 2);
  V << 0, 0, 1, 0, 0, 1;
  EXPECT_THROW(MeshField(V, {{0, 1, 3}}, Weights::Ones(3, 1)), std::invalid_argument);   // index out of range
  EXPECT_THROW(MeshField(V, {{0, 1, 1}}, Weights::Ones(3, 1)), std::invalid_argument);   // zero area
  EXPECT_THROW(MeshField(V, {{0, 1, 2}}, Weights::Ones(2, 1)), std::invalid_argument);   // weights rows
  EXPECT_THROW(MeshField(V, {}, Weights::Ones(3, 1)), std::invalid_argument);            // no triangles
  Points Vn = V;
  Vn(1, 0) = std::nan("");
  EXPECT_THROW(MeshField(Vn, {{0, 1, 2}}, Weights::Ones(3, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace kc
