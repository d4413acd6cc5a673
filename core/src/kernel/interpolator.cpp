#include "kc/core/kernel/interpolator.h"

#include <Eigen/Dense>
#include <chrono>
#include <stdexcept>
#include <string>

#include "kc/core/parallel.h"
#include "kc/core/spatial_grid.h"
#include "../sparse_cholesky.h"
#include "kc/core/timing.h"

namespace kc {
namespace {

using ColMatrix = Eigen::MatrixXd;
using Poly = Eigen::Matrix<double, Eigen::Dynamic, 3>;  // #S×3 polynomial basis [1 x̂ ŷ]

/// Relative pivot below which K is treated as numerically singular (its condition number is then
/// ≳ 1e12 and the interpolant is dominated by round-off).
constexpr double kMinRelativePivot = 1e-12;

const char* kSigmaAdvice =
    "the kernel matrix is not positive definite: sigma is too large for the sample spacing "
    "(keep sigma near 3·spacing/π, thesis 3.28), or samples nearly coincide";

}  // namespace

struct KernelInterpolator::Impl {
  Points X;
  GaussianKernel kernel;
  InterpMode mode = InterpMode::Exact;
  detail::PermutedCholesky llt;  // of K; K itself is not kept
  SpatialGrid grid;
  Eigen::VectorXd widths;  // σ at each sample (variable-width kernel only)
  bool ok = false;
  bool evaluable = false;  // X, kernel, mode and grid set
  // Exact mode: polynomial basis in centred, scaled coordinates x̂ = (x − c)/s.
  Vec2 center = Vec2::Zero();
  double polyScale = 1.0;
  Poly P;      // #S×3
  Poly KinvP;  // K⁻¹P
  Eigen::LDLT<Eigen::Matrix3d> schur;  // of PᵀK⁻¹P

  ColMatrix solveK(const ColMatrix& rhs) const { return llt.solve(rhs); }

  /// Solves [K P; Pᵀ 0][U; B̂] = [R1; R2] with the Schur complement (Exact mode), or K U = R1.
  void augmentedSolve(const ColMatrix& R1, const Eigen::Matrix<double, 3, Eigen::Dynamic>& R2, ColMatrix& U,
                      Eigen::Matrix<double, 3, Eigen::Dynamic>& Bn) const {
    U = solveK(R1);
    if (mode == InterpMode::Thesis) {
      Bn.setZero(3, R1.cols());
      return;
    }
    // PᵀU = R2 with U = K⁻¹(R1 − P B̂)  ⇒  (PᵀK⁻¹P) B̂ = PᵀK⁻¹R1 − R2.
    Bn = schur.solve(KinvP.transpose() * R1 - R2);
    U.noalias() -= KinvP * Bn;
  }
};

KernelInterpolator::KernelInterpolator() : m_impl(std::make_unique<Impl>()) {}
KernelInterpolator::~KernelInterpolator() = default;
KernelInterpolator::KernelInterpolator(KernelInterpolator&&) noexcept = default;
KernelInterpolator& KernelInterpolator::operator=(KernelInterpolator&&) noexcept = default;

namespace {
/// The checks and the data compute() and prepare() share.
template <class Impl>
std::unique_ptr<Impl> newImpl(const Points& X, const GaussianKernel& kernel, InterpMode mode) {
  if (X.rows() == 0) throw std::invalid_argument("interpolator: no samples");
  if (!X.allFinite()) throw std::invalid_argument("interpolator: sample positions must be finite");
  if (!(kernel.sigma > 0.0) || !std::isfinite(kernel.sigma))
    throw std::invalid_argument("interpolator: sigma must be positive and finite");
  auto impl = std::make_unique<Impl>();
  impl->X = X;
  impl->kernel = kernel;
  impl->mode = mode;
  if (kernel.variable()) impl->widths = kernel.widthsAt(X);
  return impl;
}
}  // namespace

void KernelInterpolator::prepare(const Points& X, const GaussianKernel& kernel, InterpMode mode) {
  auto impl = newImpl<Impl>(X, kernel, mode);
  impl->grid.build(X, kernel.cutoff());
  impl->evaluable = true;
  m_impl = std::move(impl);
}

InterpolatorReport KernelInterpolator::compute(const Points& X, const GaussianKernel& kernel, InterpMode mode) {
  const auto t0 = std::chrono::steady_clock::now();
  SparseMatrix K = assembleKernelMatrix(X, kernel);
  const double assembly = secondsSince(t0);
  InterpolatorReport report = compute(X, kernel, mode, std::move(K));
  report.assembleSeconds += assembly;
  return report;
}

InterpolatorReport KernelInterpolator::compute(const Points& X, const GaussianKernel& kernel, InterpMode mode, SparseMatrix&& K) {
  auto impl = newImpl<Impl>(X, kernel, mode);
  if (K.rows() != X.rows() || K.cols() != X.rows())
    throw std::invalid_argument("interpolator: K is " + std::to_string(K.rows()) + "×" + std::to_string(K.cols()) + " but there are " +
                                std::to_string(X.rows()) + " samples");
  InterpolatorReport report;

  auto t0 = std::chrono::steady_clock::now();
  impl->grid.build(X, kernel.cutoff());
  report.nonZeros = K.nonZeros();
  report.assembleSeconds = secondsSince(t0);

  t0 = std::chrono::steady_clock::now();
  impl->llt.compute(std::move(K));
  report.status = SolveStatus::Ok;
  if (impl->llt.outOfMemory()) {
    report.status = SolveStatus::OutOfMemory;
    report.advice = "the Cholesky factor of the kernel matrix (" + std::to_string(X.rows()) + " samples, " +
                    std::to_string(report.nonZeros) + " non-zeros) does not fit in memory: use a larger spacing or a smaller sigma";
  } else if (const double ratio = impl->llt.ok() ? impl->llt.pivotRatio() : 0.0; !(ratio > 0.0) || !std::isfinite(ratio)) {
    report.status = SolveStatus::Singular;  // not positive definite
    report.advice = kSigmaAdvice;
  } else if (ratio < kMinRelativePivot) {
    report.status = SolveStatus::Singular;
    report.advice =
        "the kernel matrix is numerically singular: sigma is too large for the sample spacing "
        "(keep sigma near 3·spacing/π, thesis 3.28), or samples nearly coincide";
  }
  if (report.status == SolveStatus::Ok && mode == InterpMode::Exact) {
    const Index n = X.rows();
    impl->center = X.colwise().mean().transpose();
    const double extent = (X.rowwise() - impl->center.transpose()).cwiseAbs().maxCoeff();
    impl->polyScale = extent > 0.0 ? extent : 1.0;
    impl->P.resize(n, 3);
    impl->P.col(0).setOnes();
    impl->P.col(1) = (X.col(0).array() - impl->center.x()) / impl->polyScale;
    impl->P.col(2) = (X.col(1).array() - impl->center.y()) / impl->polyScale;
    impl->KinvP = impl->solveK(impl->P);
    Eigen::Matrix3d S = impl->P.transpose() * impl->KinvP;
    S = 0.5 * (S + S.transpose()).eval();
    impl->schur.compute(S);
    const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S, Eigen::EigenvaluesOnly).eigenvalues();
    if (!(ev(0) > 1e-12 * ev(2))) {
      report.status = SolveStatus::Singular;
      report.advice = "the samples are collinear: the linear part of the exact interpolant is undetermined "
                      "(use the thesis interpolation or add samples off the line)";
    }
  }
  report.factorSeconds = secondsSince(t0);
  impl->ok = report.status == SolveStatus::Ok;
  impl->evaluable = impl->ok;
  m_impl = std::move(impl);
  return report;
}

bool KernelInterpolator::ok() const { return m_impl->ok; }
void KernelInterpolator::releaseFactorization() {
  m_impl->llt.release();
  m_impl->P = Poly();
  m_impl->KinvP = Poly();
  m_impl->ok = false;
}
bool KernelInterpolator::evaluable() const { return m_impl->evaluable; }
InterpMode KernelInterpolator::mode() const { return m_impl->mode; }
const GaussianKernel& KernelInterpolator::kernel() const { return m_impl->kernel; }
const Points& KernelInterpolator::samples() const { return m_impl->X; }
const Eigen::VectorXd& KernelInterpolator::widths() const { return m_impl->widths; }

KernelCoefficients KernelInterpolator::solve(const Weights& W, int refinementSteps) const {
  const Impl& d = *m_impl;
  if (!d.ok) throw std::logic_error("interpolator: solve() called without a successful compute()");
  if (W.rows() != d.X.rows())
    throw std::invalid_argument("interpolator: W has " + std::to_string(W.rows()) + " rows but there are " +
                                std::to_string(d.X.rows()) + " samples");
  if (!W.allFinite()) throw std::invalid_argument("interpolator: W must be finite");
  const Index m = W.cols();
  const ColMatrix Wc = W;
  ColMatrix U;
  Eigen::Matrix<double, 3, Eigen::Dynamic> Bn;
  d.augmentedSolve(Wc, Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, m), U, Bn);
  // Optional iterative refinement on the full system (each step costs one more solve; K is
  // assembled again for it, the factorization does not keep it).
  const SparseMatrix K = refinementSteps > 0 ? assembleKernelMatrix(d.X, d.kernel) : SparseMatrix();
  for (int step = 0; step < refinementSteps; ++step) {
    ColMatrix R1 = Wc - K * U;
    Eigen::Matrix<double, 3, Eigen::Dynamic> R2 = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, m);
    if (d.mode == InterpMode::Exact) {
      R1.noalias() -= d.P * Bn;
      R2.noalias() -= d.P.transpose() * U;
    }
    ColMatrix dU;
    Eigen::Matrix<double, 3, Eigen::Dynamic> dB;
    d.augmentedSolve(R1, R2, dU, dB);
    U += dU;
    Bn += dB;
  }

  KernelCoefficients coef;
  coef.U = U;
  // Back to raw coordinates: b0 + b1 x̂ + b2 ŷ = (b0 − c·b/s) + (b1/s) x + (b2/s) y.
  coef.B.resize(3, m);
  coef.B.row(1) = Bn.row(1) / d.polyScale;
  coef.B.row(2) = Bn.row(2) / d.polyScale;
  coef.B.row(0) = Bn.row(0) - d.center.x() * coef.B.row(1) - d.center.y() * coef.B.row(2);
  if (d.mode == InterpMode::Thesis) coef.B.setZero();
  return coef;
}

void KernelInterpolator::solveColumns(const Weights& W, std::span<const Index> columns, KernelCoefficients& coef) const {
  const Index m = W.cols();
  if (coef.U.rows() != W.rows() || coef.U.cols() != m || coef.B.cols() != m)
    throw std::invalid_argument("interpolator: solveColumns needs coefficients of the same shape as W");
  if (columns.empty()) return;
  Weights Wsub(W.rows(), static_cast<Index>(columns.size()));
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const Index c = columns[k];
    if (c < 0 || c >= m) throw std::invalid_argument("interpolator: column " + std::to_string(c) + " out of range");
    Wsub.col(static_cast<Index>(k)) = W.col(c);
  }
  const KernelCoefficients sub = solve(Wsub);
  for (std::size_t k = 0; k < columns.size(); ++k) {
    coef.U.col(columns[k]) = sub.U.col(static_cast<Index>(k));
    coef.B.col(columns[k]) = sub.B.col(static_cast<Index>(k));
  }
}

namespace {
void checkEval(const Points& X, const KernelCoefficients& coef, const Points& P) {
  if (coef.U.rows() != X.rows())
    throw std::invalid_argument("interpolator: coefficients have " + std::to_string(coef.U.rows()) +
                                " rows but there are " + std::to_string(X.rows()) + " samples");
  if (coef.B.cols() != coef.U.cols()) throw std::invalid_argument("interpolator: U and B disagree on m");
  if (!P.allFinite()) throw std::invalid_argument("interpolator: query points must be finite");
}
}  // namespace

Weights KernelInterpolator::evaluate(const KernelCoefficients& coef, const Points& P) const {
  const Impl& d = *m_impl;
  checkEval(d.X, coef, P);
  const Index m = coef.U.cols();
  Weights out(P.rows(), m);
  const double theta = d.kernel.cutoff();
  parallelFor(P.rows(), [&](Index p) {
    const Vec2 x = P.row(p).transpose();
    auto row = out.row(p);
    row = coef.B.row(0) + x.x() * coef.B.row(1) + x.y() * coef.B.row(2);
    if (d.kernel.variable()) {
      const double sx = d.kernel.widthAt(x);
      d.grid.forEachWithin(x, d.kernel.reach(sx), [&](Index j, double d2) {
        const double k = d.kernel(d2, sx, d.widths(j));
        if (k != 0.0) row.noalias() += k * coef.U.row(j);
      });
      return;
    }
    d.grid.forEachWithin(x, theta, [&](Index j, double d2) { row.noalias() += d.kernel(d2) * coef.U.row(j); });
  });
  return out;
}

void KernelInterpolator::evaluateGradient(const KernelCoefficients& coef, const Points& P, Weights& dWdx,
                                          Weights& dWdy) const {
  const Impl& d = *m_impl;
  checkEval(d.X, coef, P);
  const Index m = coef.U.cols();
  dWdx.resize(P.rows(), m);
  dWdy.resize(P.rows(), m);
  const double theta = d.kernel.cutoff();
  const double inv2 = 1.0 / (d.kernel.sigma * d.kernel.sigma);
  parallelFor(P.rows(), [&](Index p) {
    const Vec2 x = P.row(p).transpose();
    auto gx = dWdx.row(p);
    auto gy = dWdy.row(p);
    gx = coef.B.row(1);
    gy = coef.B.row(2);
    if (d.kernel.variable()) {  // the Gibbs kernel's gradient (GaussianKernel::gradientFactor)
      Vec2 g = Vec2::Zero();
      const double sx = d.kernel.widthAt(x, g);
      d.grid.forEachWithin(x, d.kernel.reach(sx), [&](Index j, double d2) {
        const double k = d.kernel(d2, sx, d.widths(j));
        if (k == 0.0) return;
        const Vec2 f = k * d.kernel.gradientFactor(x - Vec2(d.X.row(j)), sx, g, d.widths(j));
        gx.noalias() += f.x() * coef.U.row(j);
        gy.noalias() += f.y() * coef.U.row(j);
      });
      return;
    }
    // ∇k(x, x_j) = −k(x, x_j)(x − x_j)/σ² (3.42).
    d.grid.forEachWithin(x, theta, [&](Index j, double d2) {
      const double k = d.kernel(d2) * inv2;
      gx.noalias() -= (k * (x.x() - d.X(j, 0))) * coef.U.row(j);
      gy.noalias() -= (k * (x.y() - d.X(j, 1))) * coef.U.row(j);
    });
  });
}

Eigen::Matrix2d deformationJacobian(const Vec2& x, const Eigen::VectorXd& w, const Eigen::VectorXd& dwdx,
                                    const Eigen::VectorXd& dwdy, const std::vector<Affine2>& T) {
  const Index m = w.size();
  if (dwdx.size() != m || dwdy.size() != m || static_cast<Index>(T.size()) != m)
    throw std::invalid_argument("deformationJacobian: w, ∇w and T must all have m entries");
  // (3.39): J f = Σ_i w_i A_i + Σ_i (T_i x̃) ∇w_iᵀ, with T_i = [A_i | t_i] and x̃ = (x, 1).
  Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
  const Eigen::Vector3d xh(x.x(), x.y(), 1.0);
  for (Index i = 0; i < m; ++i) {
    const Affine2& Ti = T[static_cast<std::size_t>(i)];
    const Vec2 Tx = Ti * xh;
    J += w(i) * Ti.leftCols<2>();
    J.col(0) += dwdx(i) * Tx;
    J.col(1) += dwdy(i) * Tx;
  }
  return J;
}

}  // namespace kc
