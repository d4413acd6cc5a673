#include "kc/core/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace kc {
namespace {

void checkControls(const Weights& W, const Points& C, const char* what) {
  if (W.cols() != C.rows())
    throw std::invalid_argument(std::string(what) + ": W has " + std::to_string(W.cols()) + " columns but there are " +
                                std::to_string(C.rows()) + " control points");
}

}  // namespace

double partitionOfUnityError(const Weights& W) {
  if (W.rows() == 0) return 0.0;
  return (W.rowwise().sum().array() - 1.0).abs().maxCoeff();
}

double reproductionError(const Weights& W, const Points& C, const Points& P) {
  checkControls(W, C, "reproductionError");
  if (W.rows() != P.rows()) throw std::invalid_argument("reproductionError: W and P have different row counts");
  if (W.rows() == 0) return 0.0;
  return (W * C - P).cwiseAbs().maxCoeff();
}

double lagrangeError(const Weights& Wc) {
  if (Wc.rows() != Wc.cols()) throw std::invalid_argument("lagrangeError: expects W at the m control points (m×m)");
  if (Wc.rows() == 0) return 0.0;
  return (Wc - Weights::Identity(Wc.rows(), Wc.cols())).cwiseAbs().maxCoeff();
}

double edgeLinearityError(const Weights& W, const Points& C, const Points& P,
                          const std::vector<std::array<int, 2>>& edgeEnds) {
  checkControls(W, C, "edgeLinearityError");
  if (W.rows() != P.rows() || static_cast<Index>(edgeEnds.size()) != P.rows())
    throw std::invalid_argument("edgeLinearityError: W, P and edgeEnds must have one entry per point");
  const Index m = C.rows();
  double err = 0.0;
  for (Index p = 0; p < P.rows(); ++p) {
    const auto [k, l] = edgeEnds[static_cast<std::size_t>(p)];
    if (k < 0 || l < 0 || k >= m || l >= m || k == l)
      throw std::invalid_argument("edgeLinearityError: point " + std::to_string(p) + " names no valid edge");
    const Vec2 ck = C.row(k), cl = C.row(l), x = P.row(p);
    const double len2 = (ck - cl).squaredNorm();
    // Linear weights on the edge (thesis 4.7a, 4.7b); every other weight should vanish.
    const double wk = (x - cl).dot(ck - cl) / len2, wl = (x - ck).dot(cl - ck) / len2;
    for (Index i = 0; i < m; ++i) {
      const double target = i == k ? wk : (i == l ? wl : 0.0);
      err = std::max(err, std::abs(W(p, i) - target));
    }
  }
  return err;
}

double minWeight(const Weights& W) {
  return W.size() == 0 ? std::numeric_limits<double>::infinity() : W.minCoeff();
}

Index negativeCount(const Weights& W, double threshold) { return (W.array() < -threshold).count(); }

LocalityStats localityStats(const Weights& W, const Eigen::VectorXd& area, const std::vector<double>& t) {
  if (area.size() != W.rows()) throw std::invalid_argument("localityStats: area must have one entry per row of W");
  if ((area.array() < 0.0).any() || !area.allFinite())
    throw std::invalid_argument("localityStats: areas must be finite and non-negative");
  const double total = area.sum();
  if (!(total > 0.0)) throw std::invalid_argument("localityStats: total area must be positive");
  const Index m = W.cols();
  LocalityStats s;
  s.t = t;
  s.P.assign(t.size(), 0.0);
  s.Q.assign(static_cast<std::size_t>(m) + 1, 0.0);
  if (m == 0) {
    s.Q[0] = 1.0;
    return s;
  }
  const double negligible = 1e-3 / static_cast<double>(m);  // LBC paper, threshold of (21)
  std::vector<double> areaWithCount(static_cast<std::size_t>(m) + 1, 0.0);
  for (Index p = 0; p < W.rows(); ++p) {
    const double a = area(p);
    int count = 0;
    for (Index i = 0; i < m; ++i) {
      const double w = W(p, i);
      if (w > negligible) ++count;
      // (19)–(20): P(t) = (1/m) Σ_i area{|w_i| ≤ t} / area.
      for (std::size_t k = 0; k < t.size(); ++k)
        if (std::abs(w) <= t[k]) s.P[k] += a;
    }
    areaWithCount[static_cast<std::size_t>(count)] += a;
    s.meanInfluencing += a * count;
    if (a > 0.0) s.maxInfluencing = std::max(s.maxInfluencing, count);
  }
  for (double& v : s.P) v /= total * static_cast<double>(m);
  // (21): Q(k) = area{σ ≥ k} / area, a suffix sum of the histogram of σ.
  double acc = 0.0;
  for (Index k = m; k >= 0; --k) {
    acc += areaWithCount[static_cast<std::size_t>(k)];
    s.Q[static_cast<std::size_t>(k)] = acc / total;
  }
  s.Q[0] = 1.0;
  s.meanInfluencing /= total;
  return s;
}

}  // namespace kc
