#pragma once
/// Properties of weights (thesis Tables 6.1–6.4) and locality statistics (LBC paper eq. 19–21).
/// One function per property; used by tests, `kcwarp-cli stats` and the GUI's diagnostics.

#include <array>
#include <vector>

#include "kc/core/types.h"

namespace kc {

/// max_p |Σ_i w_i(p) − 1| over rows of W (#P×m).
double partitionOfUnityError(const Weights& W);
/// max_p |Σ_i w_i(p) c_i − p|_∞ over rows of W, for query points P (#P×2) and controls C (m×2).
double reproductionError(const Weights& W, const Points& C, const Points& P);
/// max_{i,j} |w_i(c_j) − δ_ij|, for W evaluated at the control points (m×m).
double lagrangeError(const Weights& Wc);
/// Max deviation from the linear weights (4.7) at points on cage edges: rows of W at points
/// P lying on edges (edgeEnds[p] = (k, l)).
double edgeLinearityError(const Weights& W, const Points& C, const Points& P,
                          const std::vector<std::array<int, 2>>& edgeEnds);
/// Smallest weight.
double minWeight(const Weights& W);
/// Number of weights below −threshold (default 1e-6).
Index negativeCount(const Weights& W, double threshold = 1e-6);

/// LBC paper (19)–(21) over points P with area elements `area` (#P, e.g. pixel areas inside the
/// cage): P(t) = mean_i φ_i(t) with φ_i(t) = area{|w_i| ≤ t} / total area (19, 20), and
/// Q(k) = area{σ ≥ k} / total area with σ(x) = #{i : w_i(x) > 10⁻³/m} (21).
struct LocalityStats {
  std::vector<double> t;   ///< Thresholds at which P is tabulated.
  std::vector<double> P;   ///< P(t).
  std::vector<double> Q;   ///< Q(k) for k = 0..m (Q[0] = 1).
  double meanInfluencing = 0.0;  ///< Area-weighted mean of σ(x).
  int maxInfluencing = 0;        ///< max σ(x).
};
LocalityStats localityStats(const Weights& W, const Eigen::VectorXd& area, const std::vector<double>& t);

}  // namespace kc
