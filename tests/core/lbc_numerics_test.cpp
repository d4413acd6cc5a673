// The two numerical pieces under the LBC solver (core/src/lbc, private): the certificate's inner
// LP against enumeration of all triangles of controls, and the column-block Cholesky solve
// against Eigen's sparse Cholesky.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <cstring>
#include <limits>
#include <random>

#include "../../core/src/lbc/barycentric_lp.h"
#include "../../core/src/lbc/row_block_cholesky.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/mesh_operators.h"
#include "kc/core/parallel.h"
#include "lbc_cages.h"

namespace kc {
namespace {

/// min q·w over barycentric w ≥ 0 of x by enumeration: the LP's optimum is at a vertex, a
/// triangle of controls containing x.
double enumeratedMinimum(const Points& C, const Vec2& x, const std::vector<double>& q) {
  double best = std::numeric_limits<double>::infinity();
  const Index m = C.rows();
  for (Index i = 0; i < m; ++i)
    for (Index j = i + 1; j < m; ++j)
      for (Index k = j + 1; k < m; ++k) {
        Eigen::Matrix2d A;
        A.col(0) = (C.row(j) - C.row(i)).transpose();
        A.col(1) = (C.row(k) - C.row(i)).transpose();
        if (std::abs(A.determinant()) < 1e-14) continue;
        const Vec2 l = A.inverse() * (x - Vec2(C.row(i)));
        const double l0 = 1.0 - l.x() - l.y();
        if (l0 < -1e-12 || l.x() < -1e-12 || l.y() < -1e-12) continue;
        best = std::min(best, l0 * q[std::size_t(i)] + l.x() * q[std::size_t(j)] + l.y() * q[std::size_t(k)]);
      }
  return best;
}

TEST(BarycentricLp, MatchesEnumerationAndNeverExceedsIt) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int controls : {3, 6, 10, 30}) {
    Points C(controls, 2);
    for (Index i = 0; i < controls; ++i) C.row(i) << u(rng), u(rng);
    const detail::BarycentricLp lp(C);
    std::array<int, 3> basis{-1, -1, -1};  // warm starts carried from point to point
    int tested = 0;
    for (int trial = 0; trial < 400; ++trial) {
      // A random convex combination of three controls: inside the hull.
      std::uniform_int_distribution<int> pick(0, controls - 1);
      const double a = std::abs(u(rng)), b = std::abs(u(rng)), c = std::abs(u(rng));
      const Vec2 x = (a * Vec2(C.row(pick(rng))) + b * Vec2(C.row(pick(rng))) + c * Vec2(C.row(pick(rng)))) / (a + b + c);
      std::vector<double> q(static_cast<std::size_t>(controls));
      for (double& v : q) v = u(rng);
      const double exact = enumeratedMinimum(C, x, q);
      const double warm = lp.lowerBound(x, q.data(), basis);
      std::array<int, 3> none{-1, -1, -1};
      const double cold = lp.lowerBound(x, q.data(), none);
      EXPECT_NEAR(warm, exact, 1e-10) << controls << " controls, trial " << trial;
      EXPECT_NEAR(cold, exact, 1e-10) << controls << " controls, trial " << trial;
      EXPECT_LE(warm, exact + 1e-12);
      ++tested;
    }
    EXPECT_EQ(tested, 400);
  }
}

TEST(BarycentricLp, ControlsOfTheStarCage) {
  const Points C = test::starCage().C;
  const detail::BarycentricLp lp(C);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::array<int, 3> basis{-1, -1, -1};
  for (int trial = 0; trial < 200; ++trial) {
    const Vec2 x(160.0 + 50.0 * u(rng), 160.0 + 50.0 * u(rng));  // inside the star's inner pentagon
    std::vector<double> q(static_cast<std::size_t>(C.rows()));
    for (double& v : q) v = u(rng);
    EXPECT_NEAR(lp.lowerBound(x, q.data(), basis), enumeratedMinimum(C, x, q), 1e-10) << trial;
  }
}

TEST(RowBlockCholesky, SolvesLikeEigenAndTheSameOnOneAndTwoThreads) {
  // L + M of a mesh of the L-shaped cage, interior block: the LBC Y-system.
  const CageMesh mesh = meshCageInterior(test::lCage(), {.spacing = 12.0, .sizing = nullptr});
  const TriangleGradients g = triangleGradients(mesh.V, mesh.T);
  const Index nb = mesh.boundary, n = mesh.interior();
  SparseMatrix S = stiffnessMatrix(mesh.T, g, mesh.size()).bottomRightCorner(n, n);
  for (Index v = 0; v < n; ++v) S.coeffRef(v, v) += g.vertexMass[std::size_t(nb + v)];
  detail::RowBlockCholesky chol;
  ASSERT_TRUE(chol.compute(S));
  const Eigen::SimplicialLDLT<SparseMatrix> reference(S);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // One or two blocks up to 30 columns (9: 8 + 1), four for 33 (9 + 9 + 9 + 6) and 42 (12 + 12 +
  // 12 + 6), sixteen of 15 for 225, the last one empty.
  for (Index k : {1, 7, 8, 9, 30, 33, 42, 225}) {
    RowMatrix B(n, k);
    for (Index i = 0; i < B.size(); ++i) B.data()[i] = u(rng);
    const Eigen::MatrixXd expected = reference.solve(Eigen::MatrixXd(B));
    RowMatrix one = B, two = B;
    {
      ScopedThreadCount threads(1);
      chol.solveInPlace(one);
    }
    {
      ScopedThreadCount threads(2);
      chol.solveInPlace(two);
    }
    EXPECT_LE((one - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff()) << k << " columns";
    EXPECT_EQ(0, std::memcmp(one.data(), two.data(), sizeof(double) * std::size_t(one.size()))) << k << " columns";
    RowMatrix serial = B;
    chol.solveInPlace(serial, false);
    EXPECT_EQ(0, std::memcmp(one.data(), serial.data(), sizeof(double) * std::size_t(one.size()))) << k << " columns";
  }
  SparseMatrix indefinite = S;
  indefinite.coeffRef(0, 0) = -1.0;
  EXPECT_FALSE(chol.compute(indefinite));
  EXPECT_FALSE(chol.ok());
}

}  // namespace
}  // namespace kc
