#pragma once
/// Structure lines kept exactly straight by a correction of a plane field (kernel coordinates):
///
///   w̃(x) = w(x) − Σ_k γ_k(x) e_k(x),   e_k(x) = w(f_k) − ℓ_k(t_k),   ℓ_k(t) = (1 − t) v_k,a + t v_k,b,
///
/// f_k = a_k + t_k (b_k − a_k) the point of line k nearest x (t_k clamped to [0, 1]), and v the
/// lines' end weights, linear in the field's weights at the ends (and, for parallel groups, at two
/// points beside each line's middle): v = M_contacts · M_parallel · [w(a_0); w(b_0); …; w(p_l); w(q_l); …].
///  - Parallel groups (thesis 5.11), as coupleParallelLines: the variation vectors d_l = (v_l,b −
///    v_l,a)/L_l of a group's lines become d_l = s_l d + r_l, d = Σ L_l² s_l (d̂_l − r_l) / Σ L_l²
///    (d̂_l the field's own), v_l,a/b = (w(a_l) + w(b_l) ∓ L_l d_l)/2, with r_l = w(p_l) − w(q_l),
///    p_l − q_l = u_l − s_l ū (u_l the unit direction, s_l = sgn(u_l·u_first), ū = Σ L_l² s_l u_l /
///    Σ L_l²) centred on the line's middle: 1ᵀr_l = 0 and Cᵀr_l = u_l − s_l ū as there, so the
///    lines stay parallel under translations up to the field's change over |p_l − q_l| ≤ 0.09 px.
///  - Contacts: M_contacts = I − A⁺A with one row of A per contact (1 − t_k) v_k,a + t_k v_k,b −
///    (1 − t_l) v_l,a − t_l v_l,b (LineContact): the least-norm change of the ends that makes
///    meeting lines agree where they meet.
///
/// The blend (Shepard's inverse-distance weights, with the cage as a site of zero correction):
///   γ_k = (ψ_k / d_k²) / (Σ_j ψ_j / d_j² + 1 / D),   ψ_k = (1 − d_k² / R_k²)² for d_k < R_k, else 0,
/// d_k = |x − f_k|, D = 1 / Σ_edges |x − edge|⁻² over the cage's loop edges and the sides of the
/// barrier polygons (a smooth stand-in for the squared distance to them), R_k = max(kLineCorrectionLength
/// · |b_k − a_k|, kLineCorrectionSigmas · σ); γ = 0 outside the cage and inside a barrier (the rigid
/// regions, whose weights the rigidity QP made). On line k γ_k = 1 and the others 0: w̃ = ℓ_k,
/// linear along the line (straight under any pose) to round-off, except where the line runs inside
/// a barrier. On the cage and the barriers every γ is 0: the cage's boundary weights (Lagrange
/// property, linear edges) and the rigid regions' are the field's own. γ is C¹ and fades within R_k
/// of each line.
///
/// Each e_k sums to 0 and reproduces 0 (w(f) and ℓ(t) both sum to 1 and reproduce f, the coupling
/// keeps that), so partition of unity and reproduction carry over exactly. w̃ is linear in the
/// field's coefficients: w̃(P) = E'(P)·Coef with E'(P) = E(P) − Σ_k γ_k (E(f_k) − (1 − t_k) V_k,a −
/// t_k V_k,b), V = M·E(ends), so every consumer of the field sees it through the evaluation
/// operator, and a brush stroke (new coefficients) keeps the lines straight.

#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "kc/core/cage.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc {

struct StructureLine;
struct LineContact;

/// R_k = max(kLineCorrectionLength · length, kLineCorrectionSigmas · σ): how far the correction of
/// a line reaches (before the cage stops it).
inline constexpr double kLineCorrectionLength = 0.5, kLineCorrectionSigmas = 8.0;

class LineCorrection {
 public:
  /// Base operators of the field: E(P) (#P×nodes), and ∂E/∂x, ∂E/∂y at P.
  using Evaluate = std::function<SparseRowMatrix(const Points&)>;
  using Gradients = std::function<void(const Points&, SparseRowMatrix&, SparseRowMatrix&)>;

  /// Lines inside the closed cage (validateLines; StructureLine::group ≥ 0 joins a parallel
  /// group), σ the field's largest kernel width (pixels), contacts = lineContacts(lines), barriers
  /// closed polygons (#n×2 each, n ≥ 3) left uncorrected. Throws std::invalid_argument for an open
  /// cage, a line of zero length, σ ≤ 0, or a barrier of fewer than 3 points.
  LineCorrection(const Cage& cage, std::span<const StructureLine> lines, std::span<const LineContact> contacts, double sigma,
                 std::span<const Points> barriers = {});

  /// Base weights and gradients of the field at points (#P×m; dWdx, dWdy #P×m).
  using EvaluateWeights = std::function<Weights(const Points&)>;
  using WeightGradients = std::function<void(const Points&, Weights&, Weights&)>;

  /// w̃(P) into W, which holds the base weights w(P) (#P×m) on entry: only the rows within reach of
  /// a line change (the same values as evaluation()·Coef, without building the operator).
  void correctWeights(const Points& P, Weights& W, const EvaluateWeights& evaluate) const;
  /// ∇w̃(P) into dWdx, dWdy, which hold the base gradients on entry.
  void correctGradients(const Points& P, Weights& dWdx, Weights& dWdy, const EvaluateWeights& evaluate,
                        const WeightGradients& gradients) const;

  /// E'(P) from the base evaluation operator E(P) (#P×nodes).
  SparseRowMatrix evaluation(const Points& P, const SparseRowMatrix& E, const Evaluate& evaluate) const;
  /// ∂E'/∂x and ∂E'/∂y at P from the base ones (Ex, Ey, replaced).
  void gradients(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey, const Evaluate& evaluate,
                 const Gradients& gradients) const;

  /// The number of lines.
  Index lines() const { return static_cast<Index>(m_a.size()); }
  /// R_k of line k (pixels).
  double reach(Index k) const { return m_reach[static_cast<std::size_t>(k)]; }

  /// One line's part of the correction at a point.
  struct Term {
    Index line = 0;
    double gamma = 0.0, t = 0.0;  ///< γ_k and the foot's parameter t_k.
    Vec2 gradGamma = Vec2::Zero();  ///< ∇γ_k (with `gradient`).
    Vec2 gradT = Vec2::Zero();      ///< ∇t_k: (b − a)/|b − a|² inside the segment, 0 where t is clamped.
  };
  /// The terms of the lines whose γ is not 0 at x (appended to `out`).
  void terms(const Vec2& x, std::vector<Term>& out, bool gradient) const;

 private:
  /// γ of every line at x (0 outside the cage or the reaches), and ∇γ when `gradient` is given;
  /// false when all are 0.
  bool gammas(const Vec2& x, std::vector<double>& gamma, std::vector<Vec2>* gradient = nullptr) const;
  /// The coupled end rows V = M·E(sources) (2·lines × nodes).
  SparseRowMatrix endRows(const Evaluate& evaluate) const;
  /// M_parallel (2·lines × #sources) for the groups of `lines`; appends the p_l, q_l to m_sources.
  Eigen::MatrixXd parallelCoupling(std::span<const StructureLine> lines);

  Cage m_cage;
  std::vector<std::array<int, 2>> m_edges;  // the cage's loop edges
  std::vector<Cage> m_barriers;
  std::vector<Vec2> m_a, m_b;
  std::vector<double> m_reach;
  Points m_sources;            // the ends a_0, b_0, a_1, …, then p_l, q_l of the grouped lines
  Eigen::MatrixXd m_coupling;  // M, 2·lines × #sources
};

}  // namespace kc
