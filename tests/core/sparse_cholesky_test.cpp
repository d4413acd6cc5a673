// The low-memory factorization of kernel-sized systems (core/src/sparse_cholesky.h): the same
// factor and solves as CHOLMOD's own supernodal path, to the bit.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "../../core/src/sparse_cholesky.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "point_problems.h"

// OpenBLAS's thread count, when the BLAS loaded is OpenBLAS (weak: null otherwise).
extern "C" void openblas_set_num_threads(int) __attribute__((weak));
extern "C" int openblas_get_num_threads() __attribute__((weak));

namespace kc {
namespace {

using detail::PermutedCholesky;
using detail::SupernodalCholesky;

SparseMatrix kernelMatrix() { return assembleKernelMatrix(test::jitteredGrid(40, 1.0, 0.3, 3), test::kernelFor(1.0)); }

TEST(PermutedCholesky, SolvesToTheBitAsCholmodsSupernodalPath) {
  const SparseMatrix K = kernelMatrix();
  const Eigen::MatrixXd B = test::randomWeights(K.rows(), 5, 4);
  SupernodalCholesky reference;
  reference.compute(K);
  ASSERT_EQ(reference.info(), Eigen::Success);
  PermutedCholesky llt;
  llt.compute(SparseMatrix(K));
  ASSERT_TRUE(llt.ok());
  const Eigen::MatrixXd X = llt.solve(B), R = reference.solve(B);
  EXPECT_TRUE(X == R) << "max difference " << (X - R).cwiseAbs().maxCoeff();
  EXPECT_EQ(llt.pivotRatio(), reference.pivotRatio());
  EXPECT_LE((K * X - B).cwiseAbs().maxCoeff(), 1e-8 * B.cwiseAbs().maxCoeff());
}

TEST(PermutedCholesky, ConsumesTheMatrixAndReadsOnlyItsLowerTriangle) {
  const SparseMatrix K = kernelMatrix();
  const Eigen::MatrixXd B = test::randomWeights(K.rows(), 2, 5);
  SparseMatrix full = K;
  PermutedCholesky a, b;
  a.compute(std::move(full));
  EXPECT_EQ(full.nonZeros(), 0) << "the matrix was released";
  SparseMatrix lower = K.triangularView<Eigen::Lower>();
  b.compute(std::move(lower));
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE(a.solve(B) == b.solve(B));
}

TEST(PermutedCholesky, ReportsAMatrixThatIsNotPositiveDefinite) {
  SparseMatrix A = kernelMatrix();
  const Index n = A.rows();
  A.coeffRef(7, 7) = -1.0;
  PermutedCholesky llt;
  llt.compute(std::move(A));
  EXPECT_FALSE(llt.ok());
  EXPECT_FALSE(llt.outOfMemory());
  EXPECT_TRUE(llt.solve(Eigen::MatrixXd::Ones(n, 1)).hasNaN());
}

TEST(PermutedCholesky, ReleaseFreesTheFactor) {
  PermutedCholesky llt;
  llt.compute(kernelMatrix());
  ASSERT_TRUE(llt.ok());
  llt.release();
  EXPECT_FALSE(llt.ok());
  EXPECT_EQ(llt.pivotRatio(), 0.0);
}

TEST(PermutedCholesky, RunsAThreadedOpenBlasOnOneThread) {
  if (!openblas_set_num_threads || !openblas_get_num_threads) GTEST_SKIP() << "the BLAS loaded is not OpenBLAS";
  openblas_set_num_threads(2);  // as OpenBLAS starts on a 2-core machine without OMP_NUM_THREADS
  PermutedCholesky llt;
  llt.compute(kernelMatrix());
  ASSERT_TRUE(llt.ok());
  EXPECT_EQ(openblas_get_num_threads(), 1) << "idle OpenBLAS workers would spin beside parallelFor's threads";
}

}  // namespace
}  // namespace kc
