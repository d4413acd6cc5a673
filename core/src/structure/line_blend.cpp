#include "kc/core/structure/line_blend.h"

#include <algorithm>
#include <limits>

#include "kc/core/structure/linear_along.h"

namespace kc {

double lineBlendReach(const Cage& cage, const StructureLine& l, double sigma) {
  double toCage = std::numeric_limits<double>::infinity();
  for (const auto& e : cage.edges)
    toCage = std::min(toCage, segmentSegmentDistance(l.a, l.b, cage.C.row(e[0]).transpose(), cage.C.row(e[1]).transpose()));
  return std::min(std::max(kLineBlendLength * l.length(), kLineBlendSigmas * sigma), toCage);
}

void blendLineNeighbourhoods(const Cage& cage, std::span<const StructureLine> lines, const SampleSet& S, double sigma,
                             const CoordinateField& field, Weights& W) {
  const Weights W0 = W;  // every line's change is measured against the weights before any
  // Per sample, over the lines whose neighbourhood holds it: Σ φ_k Δ_k, Σ φ_k and max φ_k.
  Weights sum = Weights::Zero(W.rows(), W.cols());
  Eigen::VectorXd phiSum = Eigen::VectorXd::Zero(W.rows()), phiMax = Eigen::VectorXd::Zero(W.rows());
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const auto& idx = S.lines[k];
    const Vec2 a = lines[k].a, b = lines[k].b;
    const double R = lineBlendReach(cage, lines[k], sigma), len2 = (b - a).squaredNorm();
    std::vector<Index> near;
    std::vector<double> t;
    for (Index i = 0; i < S.size(); ++i) {
      if (S.kind[static_cast<std::size_t>(i)] != SampleKind::Interior) continue;
      const Vec2 x = S.X.row(i).transpose();
      if (pointSegmentDistance(x, a, b) >= R) continue;
      near.push_back(i);
      t.push_back(std::clamp((x - a).dot(b - a) / len2, 0.0, 1.0));
    }
    if (near.empty()) continue;
    Points P(static_cast<Index>(near.size()), 2);
    for (std::size_t q = 0; q < near.size(); ++q) P.row(static_cast<Index>(q)) = ((1.0 - t[q]) * a + t[q] * b).transpose();
    const Weights Wp = field.weightsAt(P);  // the field before the line, at the projections
    const Eigen::RowVectorXd wa = W0.row(idx.front()), wb = W0.row(idx.back());
    for (std::size_t q = 0; q < near.size(); ++q) {
      const Index i = near[q];
      const double d = (S.X.row(i) - P.row(static_cast<Index>(q))).norm() / R;
      const double phi = (1.0 - d * d) * (1.0 - d * d);
      sum.row(i) += phi * ((1.0 - t[q]) * wa + t[q] * wb - Wp.row(static_cast<Index>(q)));
      phiSum(i) += phi;
      phiMax(i) = std::max(phiMax(i), phi);
    }
  }
  // One line: W_i += φ Δ. Near several (a crossing): their φ-weighted mean change, at the
  // strongest φ — next to a crossing both lines ask for about the same change, which a plain sum
  // would apply twice.
  for (Index i = 0; i < W.rows(); ++i)
    if (phiSum(i) > 0.0) W.row(i) += (phiMax(i) / phiSum(i)) * sum.row(i);
}

std::vector<Index> lineNeighbourhoodRows(const Cage& cage, std::span<const StructureLine> lines, const Points& X,
                                         double sigma) {
  std::vector<double> reach;
  for (const StructureLine& l : lines) reach.push_back(std::max(lineBlendReach(cage, l, sigma), (LinearityOptions{}.reach + 5.0) * sigma));
  std::vector<Index> rows;
  for (Index i = 0; i < X.rows(); ++i) {
    const Vec2 x = X.row(i).transpose();
    for (std::size_t k = 0; k < lines.size(); ++k) {
      if (pointSegmentDistance(x, lines[k].a, lines[k].b) <= reach[k]) {
        rows.push_back(i);
        break;
      }
    }
  }
  return rows;
}

}  // namespace kc
