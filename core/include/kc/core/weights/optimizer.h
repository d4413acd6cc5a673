#pragma once
/// Per-sample weight optimization (thesis chapter 4), every sample independent and parallel,
/// for all samples or any subset (painting re-optimizes only painted samples).

#include <algorithm>
#include <span>

#include "kc/core/types.h"
#include "kc/core/weights/sample_l1.h"
#include "kc/core/weights/sample_qec.h"
#include "kc/core/weights/sample_qp.h"

namespace kc {

enum class Method {
  QP,   ///< (4.1) min |w − w0|² s.t. Cw = x, 1ᵀw = 1, w ≥ 0 — exact optimum.
  QEC,  ///< (4.2–4.6) the same without w ≥ 0, closed form.
  L1,   ///< (4.8) min |w − w0|₁ s.t. Cw = x, 1ᵀw = 1 — exact LP optimum.
};

template <>
struct EnumNames<Method> {
  static constexpr std::array<std::pair<Method, std::string_view>, 3> table{
      {{Method::QP, "qp"}, {Method::QEC, "qec"}, {Method::L1, "l1"}}};
};

/// The QP's allowance metric (OptimizeOptions::allowance ε > 0): minimize Σ_j (w_j − w0_j)²/a_j
/// instead of |w − w0|², with a_j = min(w0_j, kAllowanceCap·ε) + ε. The correction that restores
/// reproduction (affine in the control positions under the Euclidean metric, so largest on the
/// controls farthest from the sample) is then carried by the controls the targets name: a control
/// without a target costs (kAllowanceCap + 1)× one with a target of at least kAllowanceCap·ε, and
/// all those cost the same (a painted target does not buy its control a larger share).
inline constexpr double kAllowanceCap = 10.0;
/// a_j of the allowance metric for a target w0_j and ε.
inline double allowanceOf(double target, double epsilon) {
  return std::min(std::max(0.0, target), kAllowanceCap * epsilon) + epsilon;
}

struct OptimizeOptions {
  OptimizeOptions() = default;
  /// Implicit on purpose: `OptimizeOptions{Method::L1}` and passing a Method keep working.
  OptimizeOptions(Method m) : method(m) {}  // NOLINT(google-explicit-constructor)

  Method method = Method::QP;
  QpOptions qp;  ///< Used when method == QP.
  /// QP only: ε of the allowance metric (kAllowanceCap); 0: the Euclidean QP (4.1).
  double allowance = 0.0;
  L1Options l1;  ///< Used when method == L1.
};

struct OptimizeReport {
  Index solved = 0;              ///< Samples optimized (control and edge samples included).
  Index infeasible = 0;          ///< QP samples outside the control points' convex hull (fallback used).
  Index failed = 0;              ///< Samples where the solver did not certify an optimum (fallback used).
  int maxIterations = 0;         ///< Largest per-sample iteration count.
  double seconds = 0.0;
};

/// Precomputes what every sample shares (A = [Cᵀ; 1ᵀ], (AAᵀ)⁻¹, the convex hull of C), then
/// optimizes rows of W.
class WeightOptimizer {
 public:
  WeightOptimizer() = default;
  /// C: m×2 control points. Throws std::invalid_argument when C is degenerate (collinear / < 3).
  explicit WeightOptimizer(const Points& C) { precompute(C); }
  /// Builds the shared constraint data (see ControlFrame). Same throws as the constructor.
  void precompute(const Points& C);

  /// Number of control points m (0 before precompute).
  Index size() const { return m_C.rows(); }
  const ControlFrame& frame() const { return m_frame; }

  /// Optimizes rows `subset` of W (all rows when empty) from targets W0 (#S×m). Control samples
  /// get e_i (3.18), edge samples the linear weights (4.7), other samples the method's optimum:
  /// QP (4.1, sample_qp.h), QEC (4.2–4.6, sample_qec.h) or ℓ1 (4.8, sample_l1.h). Rows outside
  /// the subset are untouched. W is resized to #S×m when the subset is empty; with a subset it
  /// must already be #S×m. Never produces NaN; infeasible QP samples use the
  /// documented fallback (see sample_qp.h). Parallel over samples; each sample writes only its
  /// own row, so results are bit-identical for any thread count.
  /// Throws std::invalid_argument on bad shapes (S.validate(m) included), non-finite W0, an
  /// out-of-range subset index or optimize() before precompute().
  OptimizeReport optimize(const SampleSet& S, const Weights& W0, Weights& W, const OptimizeOptions& options,
                          std::span<const Index> subset = {}) const;

 private:
  Points m_C;
  ControlFrame m_frame;
};

}  // namespace kc
