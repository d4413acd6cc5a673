#pragma once
/// Straight and parallel lines (thesis 5.3): line segments the user wants kept straight under
/// any translation of the control points, optionally grouped so that they stay parallel.
///
/// A deformed point is p' = p + T w(p) (T = the controls' translations), so a line stays straight
/// when the weights vary linearly along it (5.5–5.6), and lines of a group stay parallel when their
/// variation vectors d = (w(b) − w(a)) / |b − a| agree up to the sign of their directions (5.11).

#include <cstdint>
#include <span>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/sizing.h"
#include "kc/core/types.h"

namespace kc {

/// One line segment a → b (pixels) and its parallel group (−1: none).
struct StructureLine {
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
  int group = -1;
  double length() const { return (b - a).norm(); }
};

/// Shortest line kcwarp accepts, in sample spacings: a line needs a few samples along it to be
/// a line of the sampling (and its two ends must be further apart than the kernel's width).
inline constexpr double kMinLineSpacings = 3.0;

/// Checks `lines` against the cage for spacing h. Throws std::invalid_argument whose message
/// begins with "lines[k]" (k the first bad line) when a line is not finite, shorter than
/// kMinLineSpacings·h, not strictly inside the closed cage, closer than h to a cage edge, or
/// crossing or closer than h to another line; or when a parallel group has a single line
/// ("lines[k]: parallel group ... has one line"). Open cages (no interior) get no lines.
/// `graded`: for a graded sampling, which refines wherever a line comes close to the cage or to
/// another line (featureSizing), and shares a sample where lines meet (lineContacts): only lines
/// that leave the cage or overlap another are refused.
void validateLines(const Cage& cage, std::span<const StructureLine> lines, double h, bool graded = false);

/// Sample positions on one line at spacing ≈ h: round(|b − a| / h) equal pieces, both ends
/// included, from a to b (thesis 5.3.3: "regular sampling is performed on these lines"). n×2.
Points lineSamplePoints(const StructureLine& line, double h);
/// The same at the local spacing of `sizing` (segmentDivision), both ends included.
Points lineSamplePoints(const StructureLine& line, const SizingField& sizing);

/// Weights of the intermediate samples of a line from its two base points (5.6): row k of W for
/// samples[k] (samples[0] at a, samples.back() at b) becomes (1 − t_k) W(a) + t_k W(b), t_k the
/// sample's position along a → b. Partition of unity and reproduction carry over (5.5).
void interpolateLineWeights(const Points& X, std::span<const Index> samples, Weights& W);

/// Where two lines meet: line k at parameter tk (0 = its a, 1 = its b) and line l at tl, at `point`.
/// A crossing (both parameters inside (0, 1)), a line ending on another (one at 0 or 1), or two
/// lines sharing an end (both). The samples of both lines share one sample there.
struct LineContact {
  std::size_t k = 0, l = 0;
  double tk = 0.0, tl = 0.0;
  Vec2 point = Vec2::Zero();
};

/// Every pair of lines (k < l) that meets, within 1e-9 of the lines' extent. Throws
/// std::invalid_argument ("lines[l]: the line overlaps lines[k]") for collinear lines that share
/// more than a point. O(n²) in the number of lines.
std::vector<LineContact> lineContacts(std::span<const StructureLine> lines);

/// Makes the weights of lines that meet agree where they meet (both stay straight only then): the
/// end weights of the lines move by the least-norm change (all contacts at once, a complete
/// orthogonal decomposition of the contacts × end samples system) that makes
/// (1 − tk) w(a_k) + tk w(b_k) = (1 − tl) w(a_l) + tl w(b_l) at every contact, to round-off. The
/// change is a combination of the contacts' disagreements, each the difference of two rows that sum
/// to 1 and reproduce the same point, so partition of unity and reproduction are kept exactly.
/// Contacts that repeat others (three lines through one point) are redundant, not contradictory.
/// `ends[k]` = the sample indices of line k's a and b; W #S×m.
void coupleMeetingLines(std::span<const LineContact> contacts, std::span<const std::array<Index, 2>> ends, Weights& W);

/// Largest angle between the lines of a parallel group that validateLines accepts (degrees):
/// hand-drawn "parallel" lines are rarely exactly parallel; beyond this they are a mistake.
inline constexpr double kMaxParallelAngleDegrees = 5.0;

/// Parallel groups (5.11): couples the base-point weights of every group so that the variation
/// vectors d_l = (w_b − w_a) / L_l of its lines (L_l = |b_l − a_l|, u_l the unit direction,
/// s_l = sgn(u_l·u_1)) are d_l = s_l d + r_l. r_l is the least-norm vector with 1ᵀr_l = 0 and
/// Cᵀr_l = u_l − s_l ū (ū = Σ L_l² s_l u_l / Σ L_l²): zero for exactly parallel lines, which then
/// stay exactly parallel under any translation (T d_l = s_l T d). d is the least-squares choice
/// of min Σ_l |w_a,l − ŵ_a,l|² + |w_b,l − ŵ_b,l|² (ŵ the current weights):
///   d = Σ_l L_l² s_l (d̂_l − r_l) / Σ_l L_l²,  w_a,l = (ŵ_a,l + ŵ_b,l − L_l d_l) / 2,  w_b,l = w_a,l + L_l d_l.
/// Partition of unity and reproduction are kept exactly (1ᵀd_l = 0, Cᵀd_l = u_l); non-negativity
/// is not enforced. C m×2 controls, W #S×m, `ends[l]` = the sample indices of line l's a and b.
void coupleParallelLines(const Points& C, std::span<const StructureLine> lines, std::span<const std::array<Index, 2>> ends,
                         Weights& W);

/// How straight a line stays under translations only (the thesis's assumption in 5.3): the
/// points P (n×2, in order from a to b) move to p' = p + Tᵀ w(p) with Wp (n×m) their weights and
/// T (m×2) the controls' translations. Returns the largest distance of a deformed point from the
/// straight line through the deformed ends p'_0, p'_{n−1}, and (in `direction`, when given)
/// p'_{n−1} − p'_0.
double translatedLineDeviation(const Points& P, const Weights& Wp, const Points& T, Vec2* direction = nullptr);

/// How randomLines places its lines.
enum class RandomLineLayout {
  Free,          ///< Each line anywhere inside the cage, apart from the others.
  ParallelPair,  ///< The second line parallel to the first (group 0), offset sideways.
  /// Every line after the first crosses an earlier one at 20–80% of both their lengths, at least
  /// 30° from it (a window frame's X); validated as a graded bind validates them.
  Crossing,
};

/// `count` random lines that pass validateLines for the cage at spacing h, lengths uniform in
/// [minLength, maxLength], placed as `layout` says (for tests and benchmarks; deterministic in
/// `seed`). Throws std::invalid_argument when 10,000 attempts did not find them.
std::vector<StructureLine> randomLines(const Cage& cage, int count, double minLength, double maxLength, double h,
                                       std::uint64_t seed, RandomLineLayout layout = RandomLineLayout::Free);

}  // namespace kc
