#pragma once
/// Kernel interpolation of per-sample weights: the dual kernel functions of thesis 3.1 / 6.1.
/// compute() assembles K and factorizes it once per sample set; solve() is called per W.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"
#include "kc/core/solve.h"

namespace kc {

enum class InterpMode {
  Exact,   ///< K augmented with a linear polynomial: exact partition of unity and reproduction.
  Thesis,  ///< Plain w(x) = U k(x) with U = W K⁻¹ (thesis 1.9, 6.2–6.3), ~1e-3 accurate.
};

template <>
struct EnumNames<InterpMode> {
  static constexpr std::array<std::pair<InterpMode, std::string_view>, 2> table{
      {{InterpMode::Exact, "exact"}, {InterpMode::Thesis, "thesis"}}};
};

struct InterpolatorReport {
  SolveStatus status = SolveStatus::NotComputed;  ///< Ok, NotComputed, Singular or OutOfMemory.
  std::string advice;       ///< What to change when status != Ok (e.g. "σ too large for the spacing").
  Index nonZeros = 0;       ///< Non-zeros of K.
  double assembleSeconds = 0.0;
  double factorSeconds = 0.0;
};

/// Coefficients of the interpolant of one W: w(x)ᵀ = k(x)ᵀ U + [1 x y] B.
struct KernelCoefficients {
  RowMatrix U;  ///< #S×m, U = K⁻¹(W − P B) (thesis 6.2, transposed to one row per sample).
  Eigen::Matrix<double, 3, Eigen::Dynamic> B;  ///< 3×m polynomial part; zero in Thesis mode.
};

class KernelInterpolator {
 public:
  KernelInterpolator();
  ~KernelInterpolator();
  KernelInterpolator(KernelInterpolator&&) noexcept;
  KernelInterpolator& operator=(KernelInterpolator&&) noexcept;

  /// Assembles K for samples X and factorizes it (thesis 6.1); in Exact mode also the 3×3
  /// Schur complement PᵀK⁻¹P of the polynomial block. Throws std::invalid_argument on bad input
  /// (non-finite X, σ ≤ 0); a failed factorization is reported, not thrown.
  InterpolatorReport compute(const Points& X, const GaussianKernel& kernel, InterpMode mode = InterpMode::Exact);
  /// The same with K already assembled (assembleKernelMatrix(X, kernel)), which is consumed: it is
  /// released before its factor is allocated (the factorization keeps neither K nor a copy).
  /// Throws std::invalid_argument as above, and when K is not #S×#S.
  InterpolatorReport compute(const Points& X, const GaussianKernel& kernel, InterpMode mode, SparseMatrix&& K);

  /// Sets the samples, kernel and mode for evaluation only, without assembling or factorizing K
  /// (coefficients stored with a session: evaluate() and the field's operators work, solve() needs
  /// compute() first). Throws std::invalid_argument on bad input, as compute().
  void prepare(const Points& X, const GaussianKernel& kernel, InterpMode mode = InterpMode::Exact);

  /// K is factorized (compute() succeeded): solve() and solveColumns() can run.
  bool ok() const;
  /// Frees the factorization of K (the largest allocation, several times K's size): ok() becomes
  /// false, evaluable() stays as it was (as after prepare()); compute() factorizes again.
  void releaseFactorization();
  /// Samples and kernel are set (compute() or prepare()): evaluate() and evaluateGradient() can run.
  bool evaluable() const;
  InterpMode mode() const;
  const GaussianKernel& kernel() const;
  const Points& samples() const;
  /// σ at each sample (GaussianKernel::widthsAt(samples())) for a variable-width kernel; empty
  /// for a fixed width.
  const Eigen::VectorXd& widths() const;

  /// Coefficients for weights W (#S×m): U = K⁻¹W (6.2) in Thesis mode; in Exact mode the
  /// augmented system [K P; Pᵀ 0][U; B] = [W; 0] through the Schur complement. Requires ok()
  /// (throws std::logic_error otherwise; std::invalid_argument when W has the wrong row count or
  /// is not finite). refinementSteps > 0 adds steps of iterative refinement (one more solve each;
  /// the Lagrange residual is already ~1e-15 without it, see thesis_regular_sampling_test).
  KernelCoefficients solve(const Weights& W, int refinementSteps = 0) const;

  /// Re-solves only `columns` of coef for weights W (#S×m); the other columns of U and B are left
  /// as they are. Each column's system is independent (6.2), so an edit that changes a few
  /// controls' weights costs a few solves. coef must come from solve() for the same samples.
  void solveColumns(const Weights& W, std::span<const Index> columns, KernelCoefficients& coef) const;

  /// w(p) for every row of P (6.3): #P×m, computed in parallel.
  Weights evaluate(const KernelCoefficients& coef, const Points& P) const;

  /// Gradients ∂w/∂x and ∂w/∂y at every row of P (3.41–3.43): two #P×m matrices.
  void evaluateGradient(const KernelCoefficients& coef, const Points& P, Weights& dWdx, Weights& dWdy) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

/// Jacobian of the linear-blend-skinning map f(x) = Σ_i w_i(x) T_i x at x (thesis 3.39, 3.44),
/// given w(x) (m), ∇w(x) (m×2 as two m-vectors) and the handle transforms T_i.
Eigen::Matrix2d deformationJacobian(const Vec2& x, const Eigen::VectorXd& w, const Eigen::VectorXd& dwdx,
                                    const Eigen::VectorXd& dwdy, const std::vector<Affine2>& T);

}  // namespace kc
