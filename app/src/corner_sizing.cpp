#include "corner_sizing.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kc::app {
namespace {

/// The seeds of withSharpCorners (corner_sizing.h), appended to P and H.
void sharpCornerSeeds(const Cage& cage, const SizingOptions& options, double maxDegrees, double finest, std::vector<Vec2>& P,
                      std::vector<double>& H) {
  const Points& C = cage.C;
  const Index m = C.rows();
  if (m < 4 || !isClosedPolygon(cage)) return;  // the polygon i → i+1 only
  const double orientation = signedArea(C) > 0.0 ? 1.0 : -1.0;
  const double cosMax = std::cos(maxDegrees * std::numbers::pi / 180.0);
  const double hMax = options.hMax, hLow = std::max(options.hMin, finest * hMax);
  for (Index i = 0; i < m; ++i) {
    const Vec2 c = C.row(i), a = C.row((i + m - 1) % m), b = C.row((i + 1) % m);
    const Vec2 u = a - c, v = b - c;
    const double lu = u.norm(), lv = v.norm();
    if (!(lu > 0.0 && lv > 0.0)) continue;
    const double turn = (c - a).x() * (b - c).y() - (c - a).y() * (b - c).x();
    const double cosine = u.dot(v) / (lu * lv);
    if (turn * orientation >= 0.0 || cosine <= cosMax) continue;  // convex, or an open angle
    const double sine = std::sqrt(std::max(0.0, 1.0 - cosine * cosine));
    for (const auto& [dir, length] : {std::pair<Vec2, double>{u / lu, lu}, std::pair<Vec2, double>{v / lv, lv}}) {
      for (double s = 0.0; s <= length;) {
        const double h = std::clamp(s * sine / kSharpCornerSamples, hLow, hMax);
        if (h >= hMax) break;
        P.push_back(c + s * dir);
        H.push_back(h);
        s += 0.5 * h;
      }
    }
  }
}

}  // namespace

SizingField withSharpCorners(const Cage& cage, const SizingOptions& options, const SizingField& h) {
  std::vector<Vec2> P;
  std::vector<double> H;
  sharpCornerSeeds(cage, options, kSharpCornerDegrees, kSharpCornerFinest, P, H);
  if (P.empty()) return h;
  const Index n = h.graded() ? h.seeds().rows() : 0;
  Points S(n + static_cast<Index>(P.size()), 2);
  Eigen::VectorXd sizes(S.rows()), slopes = Eigen::VectorXd::Constant(S.rows(), options.gradation);
  if (n > 0) {
    S.topRows(n) = h.seeds();
    sizes.head(n) = h.sizes();
    if (h.slopes().size() > 0) slopes.head(n) = h.slopes();
  }
  for (std::size_t k = 0; k < P.size(); ++k) {
    S.row(n + static_cast<Index>(k)) = P[k].transpose();
    sizes(n + static_cast<Index>(k)) = H[k];
  }
  return SizingField(options.hMax, options.gradation, S, sizes, h.form(), slopes);
}

}  // namespace kc::app
