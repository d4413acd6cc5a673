#include "dense_blas.h"

#include "blas_threads.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <stdexcept>

// The Fortran interface (every BLAS and LAPACK has it); the trailing lengths are the hidden
// arguments of the character flags (gfortran's convention; C implementations ignore them).
extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n, const double* alpha,
            const double* a, const int* lda, double* b, const int* ldb, std::size_t, std::size_t, std::size_t, std::size_t);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a, const int* lda,
            const double* beta, double* c, const int* ldc, std::size_t, std::size_t);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* b, const int* ldb, const double* beta, double* c, const int* ldc, std::size_t, std::size_t);
}

namespace kc::blas {
namespace {

int narrow(Eigen::Index v) {
  if (v < 0 || v > std::numeric_limits<int>::max()) throw std::length_error("a dense matrix is too large for BLAS's 32-bit sizes");
  return int(v);
}

/// A leading dimension of at least 1 (BLAS refuses 0 even for empty matrices).
int lead(Eigen::Index stride, Eigen::Index rows) { return narrow(std::max<Eigen::Index>({stride, rows, 1})); }

}  // namespace

bool cholesky(Eigen::Ref<Eigen::MatrixXd> A) {
  detail::serialBlas();
  const int n = narrow(A.rows()), lda = lead(A.outerStride(), A.rows());
  if (n == 0) return true;
  int info = 0;
  dpotrf_("L", &n, A.data(), &lda, &info, 1);
  return info == 0;
}

void solveLower(const Eigen::Ref<const Eigen::MatrixXd>& L, Eigen::Ref<Eigen::MatrixXd> B, bool transpose) {
  detail::serialBlas();
  const int m = narrow(B.rows()), n = narrow(B.cols());
  if (m == 0 || n == 0) return;
  const int lda = lead(L.outerStride(), L.rows()), ldb = lead(B.outerStride(), B.rows());
  const double one = 1.0;
  dtrsm_("L", "L", transpose ? "T" : "N", "N", &m, &n, &one, L.data(), &lda, B.data(), &ldb, 1, 1, 1, 1);
}

void solveLowerTransposeRight(const Eigen::Ref<const Eigen::MatrixXd>& L, Eigen::Ref<Eigen::MatrixXd> B) {
  detail::serialBlas();
  const int m = narrow(B.rows()), n = narrow(B.cols());
  if (m == 0 || n == 0) return;
  const int lda = lead(L.outerStride(), L.rows()), ldb = lead(B.outerStride(), B.rows());
  const double one = 1.0;
  dtrsm_("R", "L", "T", "N", &m, &n, &one, L.data(), &lda, B.data(), &ldb, 1, 1, 1, 1);
}

void rankUpdateLower(Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& A, double alpha, double beta, bool transposeA) {
  detail::serialBlas();
  const int n = narrow(C.rows()), k = narrow(transposeA ? A.rows() : A.cols());
  if (n == 0) return;
  const int lda = lead(A.outerStride(), A.rows()), ldc = lead(C.outerStride(), C.rows());
  dsyrk_("L", transposeA ? "T" : "N", &n, &k, &alpha, A.data(), &lda, &beta, C.data(), &ldc, 1, 1);
}

void multiply(Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& A, bool transposeA,
              const Eigen::Ref<const Eigen::MatrixXd>& B, bool transposeB, double alpha, double beta) {
  detail::serialBlas();
  const int m = narrow(C.rows()), n = narrow(C.cols()), k = narrow(transposeA ? A.rows() : A.cols());
  if (m == 0 || n == 0) return;
  const int lda = lead(A.outerStride(), A.rows()), ldb = lead(B.outerStride(), B.rows()), ldc = lead(C.outerStride(), C.rows());
  dgemm_(transposeA ? "T" : "N", transposeB ? "T" : "N", &m, &n, &k, &alpha, A.data(), &lda, B.data(), &ldb, &beta, C.data(), &ldc, 1, 1);
}

}  // namespace kc::blas
