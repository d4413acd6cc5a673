#pragma once
/// The sizing field of a graded sampling: the local sample spacing h(x), from the local feature
/// size of the cage, its sticks, the structure lines and the rigid polygons.
///
/// Seeds (p_i, h_i) lie along every feature where h_i = narrowSpacing(lfs(p_i)) (about lfs/k) is
/// below hMax. lfs(p) is the distance from a point p of a feature to the nearest feature that does not
/// touch p's own (the other side of a gap, a nearby line, a point of a short edge's far end).
///
/// The spacing (samplers, the LBC mesher, edge division):
///   h(x) = min(hMax, min_i (h_i + g_i · |x − p_i|)),
/// a minimum of cones of slope g_i (g, or kFineGradation at the seeds of the narrowest gaps):
/// |∇h| ≤ max_i g_i by construction.
///
/// The profile the kernel width follows (σ(x) = σ · h̃(x) / hMax), SizingForm::Smooth:
///   h̃(x) = hMax · (1 + Σ_i τ(a_i) (hMax / a_i)^p)^(−1/p),  a_i = h_i + g_i·(√(|x − p_i|² + ε_i²) − ε_i),
/// with ε_i = h_i/2, p = kSizingSoftness and τ the C² taper 1 − smootherstep from a = hMax to 2·hMax.
/// h̃ is C² (h has kinks: ridges between cones, the clamp at hMax, the cone tips, and a width with
/// kinks puts kinks into every weight along a structure line, which the lines' linear fit cannot
/// remove). h̃ ≤ h, h̃ ≥ 0.5·h (about N^(−1/p) for N near-equal cones), and
/// |∇h̃| ≤ max_i g_i·(1 + 1.875/p) (the cones' gradients in a convex combination plus the taper's slope).
/// SizingForm::Min (binds without structure lines, sessions written before the profile): h̃ = h.
/// Both equal hMax away from narrow places; a cage without one has no seeds: h ≡ h̃ ≡ hMax, the
/// uniform sampling.

#include <algorithm>
#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc {

/// A place is narrow where its width w (the local feature size, or an edge's length) is below
/// kNarrowWidth·hMax: wider places keep hMax, so a cage without narrow places samples uniformly.
/// 2 is the narrowest feature a uniform bind resolved without warning.
inline constexpr double kNarrowWidth = 2.0;
/// k, samples across a narrow place between cage edges: a place of width w ≤ hMax/(1 − 1/k)
/// gets spacing w/k, and up to kNarrowWidth·hMax the spacing ramps to hMax (narrowSpacing). The
/// kernel interpolant overshoots the weights' kink at the walls of a gap, so the controls across a
/// gap keep a small weight just inside it; k bounds that leak (with the exterior continuation's
/// two-sided blend in the gap, exterior_continuation.h). The leak against k:
/// docs/notes/measured-constants.md.
inline constexpr double kFeatureSamples = 3.5;
/// k for a gap whose middle lies outside a closed cage (between two legs, an arm and the body, a
/// wedge): its walls bound different parts, and the controls on one side weigh across the gap
/// unless it holds enough samples. Such a gap narrower than kOutsideNarrowWidth·hMax gets spacing
/// w/k (at most 3/4·hMax); a wider one keeps hMax, without a ramp: a gap refined only a little
/// leaked more than one left alone (the leak against k and the width: docs/notes/measured-constants.md).
inline constexpr double kOutsideFeatureSamples = 4.0;
/// See kOutsideFeatureSamples.
inline constexpr double kOutsideNarrowWidth = 3.0;
/// k where a structure line or a rigid polygon's side is one side of the place (see
/// kExtraNarrowWidth): such a place is refined to a quarter of its width.
inline constexpr double kExtraFeatureSamples = 4.0;
/// kNarrowWidth for a place between a structure line or a rigid polygon's side and another
/// feature: the field must be linear along a line, not only bounded across a gap, and a line a few
/// spacings from the cage or another line bends unless the place between them is refined;
/// n = kExtraFeatureSamples refines every such place to a quarter of its width.
inline constexpr double kExtraNarrowWidth = 4.0;
/// Two edges of a closed cage that share an end, with the outside between them, count as the two
/// walls of a narrow place (a wedge) where they meet at an angle below this: an arm drawn close to
/// the body meets it at the armpit at a few degrees, and the gap between them is as narrow as a
/// slit all along, though its walls share the armpit's vertex. A point at distance s from the shared
/// vertex is s·sin θ from the other wall. Wider corners, and sharp tips of the cage's inside (a
/// pointed hand: both walls bound the same part), are not.
inline constexpr double kWedgeDegrees = 30.0;
/// The finest spacing of a wedge, as a fraction of hMax: its width falls to 0 at the shared vertex,
/// and the refinement stops where the width is about kFeatureSamples times this.
inline constexpr double kWedgeFinest = 0.125;
/// g: how fast the spacing may grow away from a narrow place, |∇h| ≤ g. At 0.3 neighbouring
/// samples differ in spacing by at most ~30%, so the inverse mean shift and the variable-width
/// kernel see a locally uniform sampling; the sample count of the refinement around one narrow
/// place grows like (2π/g²)·ln(hMax/h_i), about 70 samples per factor e of refinement.
inline constexpr double kSizingGradation = 0.3;
/// The gradation of a gap between two parts of a closed cage finer than kFineSeedFraction·hMax (a
/// gap narrower than hMax: legs drawn a few pixels apart), wedges excepted: its spacing, w/4 at the
/// walls, reaches hMax in (hMax − w/4)/g, most of each part at g = kSizingGradation, and the far
/// side's weight 1–3 px inside such a narrow gap stays well below its bound either way, while gaps
/// of one to three hMax (refined less) and wedges need the gentler g. The samples and the far
/// side's weight against it: docs/notes/measured-constants.md.
inline constexpr double kFineGradation = 0.45;
/// See kFineGradation (a fraction of hMax).
inline constexpr double kFineSeedFraction = 0.25;
/// p of the smooth profile: the soft minimum blends cones within about 1/p of each other (a
/// ridge is rounded over about a/(p·g) ≈ 0.4·h either side). Smaller p is smoother (straighter
/// structure lines) and lies further below h (more samples).
inline constexpr double kSizingSoftness = 8.0;

/// The profile the kernel width follows (see above).
enum class SizingForm { Smooth, Min };

struct SizingOptions {
  double hMax = 6.0;                     ///< Spacing away from narrow places (pixels, > 0).
  double hMin = 0.05;                    ///< Smallest spacing (pixels, > 0, ≤ hMax).
  double featureSamples = kFeatureSamples;  ///< k (see kFeatureSamples).
  double extraFeatureSamples = kExtraFeatureSamples;  ///< k where a FeatureSegment is one side.
  double narrowWidth = kNarrowWidth;        ///< In units of hMax (see kNarrowWidth); ≥ 1.
  double extraNarrowWidth = kExtraNarrowWidth;  ///< The same where a FeatureSegment is one side; ≥ 1.
  double outsideFeatureSamples = kOutsideFeatureSamples;  ///< k for a gap outside a closed cage.
  double outsideNarrowWidth = kOutsideNarrowWidth;  ///< Its width limit (units of hMax); ≥ 1.
  double gradation = kSizingGradation;              ///< g in (0, 0.5].
  double fineGradation = kFineGradation;            ///< In [gradation, 0.5] (see kFineGradation).
  double fineBelow = kFineSeedFraction;             ///< See kFineSeedFraction (a fraction of hMax).
  double wedgeDegrees = kWedgeDegrees;   ///< See kWedgeDegrees; 0: edges that share an end never count.
  double wedgeFinest = kWedgeFinest;     ///< See kWedgeFinest (a fraction of hMax).
  /// Whether a gap whose middle lies outside a closed cage (between two legs, a wedge) is a narrow
  /// place. false for a sampling of the cage's inside only (the LBC mesh): each wall of such a gap
  /// is then as wide as the part it bounds.
  bool outsideGaps = true;
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
  /// From seeds: P #n×2 positions, H #n sizes (each in (0, hMax]), G #n slopes (each in
  /// [gradation, 0.5]; empty: every cone's slope is the gradation). Throws std::invalid_argument on
  /// non-finite values, sizes or slopes out of range, or g outside (0, 0.5].
  SizingField(double hMax, double gradation, const Points& P, const Eigen::VectorXd& H, SizingForm form = SizingForm::Smooth,
              const Eigen::VectorXd& G = Eigen::VectorXd());

  /// h(x).
  double operator()(const Vec2& x) const;
  /// h(x) and its gradient (g times the unit vector from the nearest active seed; 0 where h = hMax).
  double valueAndGradient(const Vec2& x, Vec2& gradient) const;
  /// h̃(x), the kernel width's profile, and its gradient when `gradient` is given.
  double profile(const Vec2& x, Vec2* gradient = nullptr) const;
  /// h̃ at every row of X (#X).
  Eigen::VectorXd profileAt(const Points& X) const;
  /// h at every row of X (#X).
  Eigen::VectorXd at(const Points& X) const;

  /// True when some seed lies below hMax (the sampling is not uniform).
  bool graded() const { return m_P.rows() > 0; }
  double hMax() const { return m_hMax; }
  /// The smallest h anywhere (the smallest seed, or hMax).
  double hMin() const { return graded() ? m_H.minCoeff() : m_hMax; }
  /// The cones' least slope g (every seed's, unless slopes() says otherwise).
  double gradation() const { return m_g; }
  /// The steepest cone's slope: |∇h| ≤ lipschitz().
  double lipschitz() const { return m_G.size() > 0 ? std::max(m_g, m_G.maxCoeff()) : m_g; }
  /// Per-seed slopes (#seeds), or empty when every cone's slope is gradation().
  const Eigen::VectorXd& slopes() const { return m_G; }
  SizingForm form() const { return m_form; }
  const Points& seeds() const { return m_P; }
  const Eigen::VectorXd& sizes() const { return m_H; }

 private:
  void buildGrid();

  /// Calls visit(s) for the seeds s in rings of grid cells around x, outwards, while a seed at the
  /// ring's distance d could have a cone below bound(): min_i (1 − g_i/2)·h_i + g·d < bound().
  template <class Bound, class Visit>
  void scanSeeds(const Vec2& x, Bound bound, Visit visit) const;
  double slope(int s) const { return m_G.size() > 0 ? m_G(s) : m_g; }
  double minForm(const Vec2& x, Vec2& gradient) const;
  double smoothForm(const Vec2& x, Vec2& gradient) const;

  double m_hMax = 1.0, m_g = kSizingGradation;
  SizingForm m_form = SizingForm::Smooth;
  Points m_P;
  Eigen::VectorXd m_H, m_G;
  double m_reach = 0.0;  // seeds farther than this never lower h below hMax
  double m_tipLow = 0.0;  // min_i (1 − g_i/2)·h_i
  double m_cell = 1.0, m_x0 = 0.0, m_y0 = 0.0;
  int m_nx = 0, m_ny = 0;
  std::vector<int> m_start, m_items;
  std::vector<double> m_cellLow;  // per cell: the lowest (1 − g_i/2)·h_i of its seeds (∞ when empty)
};

/// The spacing of a narrow place of width w (pixels) between cage edges:
///   clamp(max(w/k, w − (n − 1)·hMax), hMin, hMax),  k = featureSamples, n = narrowWidth,
/// w/k where w ≤ hMax·(n − 1)/(1 − 1/k), rising with slope 1 to hMax at w = n·hMax (continuous;
/// n = k gives w/k throughout). Where an extra segment is one side, k = extraFeatureSamples and
/// n = extraNarrowWidth. A gap between cage edges whose middle lies outside a closed cage gets the
/// finer of this and outsideSpacing.
double narrowSpacing(double width, const SizingOptions& options);
/// The spacing of a gap of width w (pixels) whose middle lies outside a closed cage:
/// clamp(w/k, hMin, hMax) for w < n·hMax, else hMax (k = outsideFeatureSamples, n = outsideNarrowWidth).
double outsideSpacing(double width, const SizingOptions& options);

/// The sizing field of a cage and further features (structure lines, rigid polygons' sides):
/// seeds every h_i/2 along each feature where h_i = narrowSpacing(lfs) < hMax, and at every
/// feature vertex whose shortest incident segment is that short; lfs and the vertex's segment
/// count with n = extraNarrowWidth where an extra segment is one side of the place (at a vertex:
/// any incident one). Features that cross or touch (within 1e-9 of the cage's extent) are split
/// there and share the point, so a crossing or a line ending on an edge is not a narrow place;
/// adjacent segments (sharing an end, also where ends of two features meet) do not count for each
/// other's lfs, except two edges of a closed cage meeting at less than wedgeDegrees with the outside
/// between them (a wedge: spacing no finer than wedgeFinest·hMax). Gaps outside the cage (wedges
/// included) count only with options.outsideGaps, and with outsideSpacing. Deterministic;
/// expected O(n log n) in the number of segments plus O(seeds · neighbours).
SizingField featureSizing(const Cage& cage, std::span<const FeatureSegment> extra, const SizingOptions& options);

/// Division of the segment a–b at the local spacing: parameters 0 = t_0 < … < t_n = 1 with
/// n = max(1, round(∫ ds / h)) pieces at equal steps of ∫ ds / h (for h ≡ hMax: t_k = k/n,
/// n = max(1, round(|b − a| / hMax)), the uniform division).
std::vector<double> segmentDivision(const Vec2& a, const Vec2& b, const SizingField& h);


}  // namespace kc
