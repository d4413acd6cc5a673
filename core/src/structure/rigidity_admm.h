#pragma once
// Private to kc::core: the rigidity QP's path for large regions (docs/rigidity.md, "Large
// regions"): ADMM to a moderate tolerance on one dense factorization, its split variable projected
// onto each constrained sample's row polytope, and the same projection applied to the stored rows
// afterwards, which makes non-negativity exact and keeps partition of unity and reproduction.

#include <Eigen/Dense>
#include <span>
#include <vector>

#include "kc/core/structure/rigidity_qp.h"
#include "kc/core/types.h"

namespace kc::detail {

/// The changes d of one constrained sample's weights that keep its partition of unity and
/// reproduction and its bound: {d ∈ R^m' : d ≥ l, Bᵀd = 0} over the m' active controls (the
/// non-zero rows Z' of Z), B (m'×k, k ≤ 3) an orthonormal basis of the complement of span Z'.
class RowPolytope {
 public:
  explicit RowPolytope(const RowMatrix& Z);
  /// The active controls (the rows of Z that are not zero), ascending.
  const std::vector<Index>& controls() const { return m_controls; }
  Index size() const { return Index(m_controls.size()); }
  /// s = the Euclidean projection of v onto {d ≥ l, Bᵀd = 0} (v, l, s of size m'), by a
  /// semismooth Newton method on the dual: s = max(l, v − Bν) with Bᵀs = 0 for the k multipliers ν
  /// (warm start in, result out). Returns false when it did not converge in 100 steps; s is then
  /// feasible all the same (v's part in span Z' scaled toward 0 until it meets the bounds).
  bool project(const double* v, const double* l, double* s, Eigen::Vector3d& nu) const;

 private:
  /// The exact solution once the free entries (v − Bν above the bound) are known: ν from their
  /// k×k system, so that Bᵀs = 0 holds to round-off. True (s and ν set) when it satisfies the
  /// projection's optimality conditions, i.e. the free set was the optimum's.
  bool polish(const Eigen::Ref<const Eigen::VectorXd>& v, const Eigen::Ref<const Eigen::VectorXd>& l, Eigen::Vector3d& nu,
              Eigen::Ref<Eigen::VectorXd> s) const;

  std::vector<Index> m_controls;
  Eigen::Matrix<double, Eigen::Dynamic, 3> m_B;  // m'×3 (zero columns beyond k)
};

struct RowProjection {
  Index changed = 0;     ///< Rows that violated a bound (and were projected).
  Index fallbacks = 0;   ///< Rows whose projection did not converge (scaled toward 0 instead).
  double largest = 0.0;  ///< The largest change of a weight.
};

/// Projects rows of dW (changes of the data weights, one column per control) onto their row
/// polytopes: row rows[r] with the bound L.row(r) (over all m controls; Z m×r as in RigidityQp).
/// Rows that keep their bounds are left as they are; dW stays zero in the inactive controls.
RowProjection projectRows(const RowMatrix& Z, const RowMatrix& L, std::span<const Index> rows, RowMatrix& dW);

/// ADMM with the row-polytope projection (docs/rigidity.md, "Large regions"), to
/// options.splittingTolerance (weights) and options.splittingDualTolerance; report.method = Splitting.
RowMatrix solveSplitting(const RigidityQp& qp, const RigidityQpOptions& options, RigidityQpReport& report);

}  // namespace kc::detail
