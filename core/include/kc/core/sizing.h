#pragma once
/// The sizing field of a graded sampling: the local sample spacing h(x), from the local feature
/// size of the cage, its sticks, the structure lines and the rigid polygons.
///
///   h(x) = min(hMax, min_i (h_i + g · |x − p_i|)),
///
/// over seeds (p_i, h_i) placed along every feature where h_i = clamp(lfs(p_i) / k, hMin, hMax) is
/// below hMax. lfs(p) is the distance from a point p of a feature to the nearest feature that does
/// not touch p's own (the other side of a gap, a nearby line, a point of a short edge's far end).
/// A minimum of g-Lipschitz cones, h is g-Lipschitz (|∇h| ≤ g) by construction, equals hMax away
/// from narrow places, and a cage without one has no seeds: h ≡ hMax, the uniform sampling.

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc {

/// Samples across the narrowest place: a gap of width w (or an edge of length w) gets spacing w/k.
/// k = 2 puts edge samples on both sides of a gap with one free sample between them, which keeps
/// the kernel matrix as well conditioned as at a feature 2h wide in a uniform sampling (the
/// narrowest a uniform bind resolved without warning).
inline constexpr double kFeatureSamples = 2.0;
/// g: how fast the spacing may grow away from a narrow place, |∇h| ≤ g. At 0.3 neighbouring
/// samples differ in spacing by at most ~30%, so the inverse mean shift and the variable-width
/// kernel see a locally uniform sampling; the sample count of the refinement around one narrow
/// place grows like (2π/g²)·ln(hMax/h_i), about 70 samples per factor e of refinement.
inline constexpr double kSizingGradation = 0.3;

struct SizingOptions {
  double hMax = 6.0;                     ///< Spacing away from narrow places (pixels, > 0).
  double hMin = 0.05;                    ///< Smallest spacing (pixels, > 0, ≤ hMax).
  double featureSamples = kFeatureSamples;
  double gradation = kSizingGradation;   ///< g in (0, 0.5].
};

/// A feature segment that is not a cage edge (a structure line, a rigid polygon's side).
struct FeatureSegment {
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
};

class SizingField {
 public:
  /// h ≡ 1 (no seeds).
  SizingField() = default;
  /// h ≡ hMax: the uniform sampling.
  static SizingField uniform(double hMax);
  /// From seeds: P #n×2 positions, H #n sizes (each in (0, hMax]). Throws std::invalid_argument on
  /// non-finite values, sizes out of range, or g outside (0, 0.5].
  SizingField(double hMax, double gradation, const Points& P, const Eigen::VectorXd& H);

  /// h(x).
  double operator()(const Vec2& x) const;
  /// h(x) and its gradient (g times the unit vector from the nearest active seed; 0 where h = hMax).
  double valueAndGradient(const Vec2& x, Vec2& gradient) const;
  /// h at every row of X (#X).
  Eigen::VectorXd at(const Points& X) const;

  /// True when some seed lies below hMax (the sampling is not uniform).
  bool graded() const { return m_P.rows() > 0; }
  double hMax() const { return m_hMax; }
  /// The smallest h anywhere (the smallest seed, or hMax).
  double hMin() const { return graded() ? m_H.minCoeff() : m_hMax; }
  double gradation() const { return m_g; }
  const Points& seeds() const { return m_P; }
  const Eigen::VectorXd& sizes() const { return m_H; }

 private:
  void buildGrid();

  double m_hMax = 1.0, m_g = kSizingGradation;
  Points m_P;
  Eigen::VectorXd m_H;
  double m_reach = 0.0;  // seeds farther than this never lower h below hMax
  double m_cell = 1.0, m_x0 = 0.0, m_y0 = 0.0;
  int m_nx = 0, m_ny = 0;
  std::vector<int> m_start, m_items;
};

/// The sizing field of a cage and further features (structure lines, rigid polygons' sides):
/// seeds every h_i/2 along each feature where lfs/k < hMax, and at every feature vertex whose
/// shortest incident segment is shorter than k·hMax. Features that cross or touch (within 1e-9 of
/// the cage's extent) are split there and share the point, so a crossing or a line ending on an
/// edge is not a narrow place; adjacent segments (sharing an end) do not count for each other's
/// lfs. Deterministic; expected O(n log n) in the number of segments plus O(seeds · neighbours).
SizingField featureSizing(const Cage& cage, std::span<const FeatureSegment> extra, const SizingOptions& options);

/// Division of the segment a–b at the local spacing: parameters 0 = t_0 < … < t_n = 1 with
/// n = max(1, round(∫ ds / h)) pieces at equal steps of ∫ ds / h (for h ≡ hMax: t_k = k/n,
/// n = max(1, round(|b − a| / hMax)), the uniform division).
std::vector<double> segmentDivision(const Vec2& a, const Vec2& b, const SizingField& h);


}  // namespace kc
