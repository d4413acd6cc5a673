#include "kc/core/kernel/kernel_matrix.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "kc/core/parallel.h"

namespace kc {
namespace {

Points randomPoints(int n, double extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, extent);
  Points X(n, 2);
  for (int i = 0; i < n; ++i) X.row(i) << u(rng), u(rng);
  return X;
}

GaussianKernel testKernel() {
  GaussianKernel k;
  k.sigma = 1.3;
  k.scale = 0.7;
  return k;
}

TEST(KernelMatrix, MatchesBruteForceAssembly) {
  const Points X = randomPoints(400, 30.0, 1);
  const GaussianKernel k = testKernel();
  const SparseMatrix K = assembleKernelMatrix(X, k);
  ASSERT_EQ(K.rows(), 400);
  ASSERT_EQ(K.cols(), 400);
  const Eigen::MatrixXd Kd = K;
  Index expectedNnz = 0;
  for (Index i = 0; i < X.rows(); ++i)
    for (Index j = 0; j < X.rows(); ++j) {
      const double r2 = (X.row(i) - X.row(j)).squaredNorm();
      if (r2 <= k.cutoff() * k.cutoff()) ++expectedNnz;
      EXPECT_NEAR(Kd(i, j), k(r2), 1e-15) << i << "," << j;
    }
  EXPECT_EQ(K.nonZeros(), expectedNnz);  // exactly the pairs within θ are stored
}

TEST(KernelMatrix, IsSymmetricWithUnitScaledDiagonal) {
  const Points X = randomPoints(500, 25.0, 2);
  const GaussianKernel k = testKernel();
  const SparseMatrix K = assembleKernelMatrix(X, k);
  const SparseMatrix Kt = K.transpose();
  EXPECT_EQ((K - Kt).norm(), 0.0);  // bit-identical: k(r²) is symmetric in its arguments
  for (Index i = 0; i < X.rows(); ++i) EXPECT_EQ(K.coeff(i, i), k.scale);
}

TEST(KernelMatrix, StoresNothingBeyondCutoff) {
  const Points X = randomPoints(300, 40.0, 3);
  const GaussianKernel k = testKernel();
  const SparseMatrix K = assembleKernelMatrix(X, k);
  for (Index c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it)
      EXPECT_LE((X.row(it.row()) - X.row(it.col())).norm(), k.cutoff() * (1 + 1e-12));
}

TEST(KernelMatrix, KernelRowsMatchBruteForce) {
  const Points X = randomPoints(300, 20.0, 4);
  const Points P = randomPoints(120, 22.0, 5);
  const GaussianKernel k = testKernel();
  const SparseRowMatrix R = kernelRows(X, P, k);
  ASSERT_EQ(R.rows(), 120);
  ASSERT_EQ(R.cols(), 300);
  const Eigen::MatrixXd Rd = R;
  for (Index p = 0; p < P.rows(); ++p)
    for (Index j = 0; j < X.rows(); ++j) EXPECT_NEAR(Rd(p, j), k((P.row(p) - X.row(j)).squaredNorm()), 1e-15);
}

TEST(KernelMatrix, KernelRowsAtSamplesEqualK) {
  const Points X = randomPoints(200, 15.0, 6);
  const GaussianKernel k = testKernel();
  const SparseMatrix K = assembleKernelMatrix(X, k);
  const SparseRowMatrix R = kernelRows(X, X, k);
  EXPECT_EQ((SparseMatrix(R) - K).norm(), 0.0);
}

TEST(KernelMatrix, ThreadCountDoesNotChangeTheResult) {
  const Points X = randomPoints(3000, 60.0, 7);
  const GaussianKernel k = testKernel();
  SparseMatrix K1, K2;
  {
    ScopedThreadCount one(1);
    K1 = assembleKernelMatrix(X, k);
  }
  {
    ScopedThreadCount two(2);
    K2 = assembleKernelMatrix(X, k);
  }
  ASSERT_EQ(K1.nonZeros(), K2.nonZeros());
  EXPECT_TRUE(std::equal(K1.innerIndexPtr(), K1.innerIndexPtr() + K1.nonZeros(), K2.innerIndexPtr()));
  EXPECT_TRUE(std::equal(K1.valuePtr(), K1.valuePtr() + K1.nonZeros(), K2.valuePtr()));
}

TEST(KernelMatrix, RejectsBadInput) {
  Points X = randomPoints(10, 5.0, 8);
  GaussianKernel k = testKernel();
  k.sigma = 0.0;
  EXPECT_THROW(assembleKernelMatrix(X, k), std::invalid_argument);
  k = testKernel();
  X(3, 1) = std::nan("");
  EXPECT_THROW(assembleKernelMatrix(X, k), std::invalid_argument);
  EXPECT_THROW(kernelRows(randomPoints(10, 5.0, 9), X, k), std::invalid_argument);
}

TEST(KernelMatrix, EmptyInputGivesEmptyMatrix) {
  const SparseMatrix K = assembleKernelMatrix(Points(0, 2), testKernel());
  EXPECT_EQ(K.rows(), 0);
  EXPECT_EQ(K.nonZeros(), 0);
}

}  // namespace
}  // namespace kc
