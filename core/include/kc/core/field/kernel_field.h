#pragma once
/// The kernel-coordinate field (thesis 1.9, 6.2–6.3): w(x)ᵀ = k(x)ᵀU + [1 x y]B, with U, B solved
/// from the per-sample weights W by the KernelInterpolator. As a CoordinateField its nodes are
/// the three polynomial terms [1 x y] (nodes 0..2; zero coefficients in Thesis mode) followed by
/// the #S samples (nodes 3..3+#S−1), and Coef = [B; U] ((3+#S)×m).

#include <memory>

#include "kc/core/field/field.h"
#include "kc/core/field/line_correction.h"
#include "kc/core/kernel/interpolator.h"

namespace kc {

class KernelField final : public CoordinateField {
 public:
  /// Number of polynomial nodes before the samples.
  static constexpr Index kPolynomialNodes = 3;

  /// Assembles K for samples X and factorizes it (KernelInterpolator::compute, thesis 6.1).
  /// The field is ready() after a successful compute() and an update() with all columns.
  InterpolatorReport compute(const Points& X, const GaussianKernel& kernel, InterpMode mode = InterpMode::Exact);
  /// The same with K = assembleKernelMatrix(X, kernel) given, and consumed (KernelInterpolator::compute).
  InterpolatorReport compute(const Points& X, const GaussianKernel& kernel, InterpMode mode, SparseMatrix&& K);

  /// A field from coefficients solved earlier (stored with a session): Coef = [B; U]
  /// ((3+#S)×m, as coefficientColumns()) for samples X, without factorizing K. It is ready() at
  /// once; the first update() factorizes K (compute) before solving. Throws std::invalid_argument
  /// on bad shapes or non-finite values.
  /// `lift` (#S×m or empty) is the lift already in Coef's U (lift()).
  void restore(const Points& X, const GaussianKernel& kernel, InterpMode mode, const RowMatrix& Coef, const RowMatrix& lift = {});

  Index controls() const override { return m_coef.U.cols(); }
  Index nodes() const override { return kPolynomialNodes + m_interp.samples().rows(); }
  bool ready() const override { return m_interp.evaluable() && m_coef.U.size() > 0; }
  /// K is factorized (after compute(), or after a restore() once update() ran).
  bool factorized() const { return m_interp.ok(); }
  /// Frees the factorization, keeping the coefficients (KernelInterpolator::releaseFactorization):
  /// the field evaluates as before and its next update() factorizes K again, as after restore().
  void releaseFactorization() { m_interp.releaseFactorization(); }

  /// Row p = [1 x y | k(p, x_j) for |p − x_j| ≤ θ] (3.32), sample columns in increasing j.
  SparseRowMatrix evaluationOperator(const Points& P) const override;
  /// Row p of ∂E/∂x = [0 1 0 | −k(p, x_j)(p_x − x_j,x)/σ²] (3.41–3.43); ∂E/∂y likewise.
  void gradientOperators(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const override;
  RowMatrix coefficientColumns(std::span<const Index> columns = {}) const override;
  FieldDomain domain() const override { return FieldDomain::Plane; }
  std::string_view kind() const override { return "kernel"; }
  void releaseWorkspace() override { releaseFactorization(); }
  bool contains(const Vec2&) const override { return true; }

  /// U, B for the sample weights W (#S×m): all columns (solve, 6.2) when `columns` is empty or the
  /// field has no coefficients of W's shape yet, otherwise only `columns` (solveColumns). A
  /// restored field factorizes K first (std::invalid_argument with the advice when it cannot).
  /// Throws std::logic_error when the factorization failed.
  void update(const Weights& W, std::span<const Index> columns = {}) override;

  /// KernelInterpolator::evaluate (6.3) — the same bits as the interpolator path; with a line
  /// correction, then LineCorrection::correctWeights; with a lobe bound, then LobeBound::apply.
  Weights weightsAt(const Points& P) const override;
  /// weightsAt without the lobe bound: E(P)·Coef, what the evaluation operator gives.
  Weights unboundedWeightsAt(const Points& P) const;
  /// KernelInterpolator::evaluateGradient (3.41–3.43); with a line correction, then
  /// LineCorrection::correctGradients; with a lobe bound, then LobeBound::applyGradients.
  void gradientsAt(const Points& P, Weights& dWdx, Weights& dWdy) const override;

  /// Keeps structure lines straight (LineCorrection): every evaluation — operators, weightsAt,
  /// gradientsAt — is of the corrected field w̃ once set; null removes it. The data weights W and
  /// the coefficients are the uncorrected field's (the correction is applied on evaluation).
  void setLineCorrection(std::shared_ptr<const LineCorrection> correction) { m_lines = std::move(correction); }
  std::shared_ptr<const LineCorrection> lineCorrection() const { return m_lines; }

  /// The lobe lift ΔU (#S×m, rows orthogonal to [1 x y] of the controls; lobe_lift.h), added to the
  /// coefficients U that update() solves: w(x)ᵀ = k(x)ᵀ(U + ΔU) + [1 x y]B. Empty: none. compute()
  /// and restore() remove it; addLift() adds to it (and to the current coefficients), setLift()
  /// replaces it (a session's, after restore()), clearLift() removes it.
  const RowMatrix& lift() const { return m_lift; }
  void addLift(const RowMatrix& dU);
  void setLift(const RowMatrix& dU);
  void clearLift() { setLift(RowMatrix()); }

  const KernelInterpolator& interpolator() const { return m_interp; }
  const KernelCoefficients& kernelCoefficients() const { return m_coef; }

 private:
  SparseRowMatrix baseEvaluation(const Points& P) const;
  void baseGradients(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const;

  KernelInterpolator m_interp;
  KernelCoefficients m_coef;
  std::shared_ptr<const LineCorrection> m_lines;
  RowMatrix m_lift;
};

}  // namespace kc
