#pragma once
/// The neighbourhood of a structure line in a kernel field (thesis 5.3.3): the interior samples
/// near a line are blended toward the line's linear weights, so that the picture next to a line
/// moves with it, and the set of samples the lines' post-processing may change.

#include <span>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/field/field.h"
#include "kc/core/structure/lines.h"
#include "kc/core/types.h"

namespace kc {

/// A line's neighbourhood reaches kLineBlendLength × its length from it, at least kLineBlendSigmas σ
/// (and never past the cage).
inline constexpr double kLineBlendLength = 0.25, kLineBlendSigmas = 4.0;

/// The reach R of line l's neighbourhood (pixels): min(max(kLineBlendLength·|l|,
/// kLineBlendSigmas·σ), distance from l to the cage's edges).
double lineBlendReach(const Cage& cage, const StructureLine& l, double sigma);

/// The interior samples near each line move with it: a line's samples jump from the field's
/// weights w(p) to the linear ones ℓ(p) (5.6), so without this the picture next to a line shears
/// and folds. Each interior sample x_i (S.kind Interior) within the reach R of line k (p_i its
/// nearest point on the line, d_i = |x_i − p_i| / R) gets
///   W_i += (1 − d_i²)² (ℓ_k(p_i) − w(p_i)),
/// ℓ_k linear between the weights W holds on entry at line k's end samples (S.lines[k] front and
/// back), w = `field` (the weights before the lines). A sample near several lines (a crossing) gets
/// (max_k φ_k / Σ_k φ_k) Σ_k φ_k Δ_k, φ_k = (1 − d_k²)², Δ_k = ℓ_k(p_k) − w(p_k): their φ-weighted
/// mean change at the strongest φ (a plain sum would apply a crossing's change twice). Each Δ_k
/// sums to 0 and reproduces 0 (ℓ(p) and w(p) both sum to 1 and reproduce p), so partition of
/// unity and reproduction stay exact; control, edge and line samples are not
/// changed. W is #S×m; S.lines has one entry per line.
void blendLineNeighbourhoods(const Cage& cage, std::span<const StructureLine> lines, const SampleSet& S, double sigma,
                             const CoordinateField& field, Weights& W);

/// The samples (rows of X, #X×2) the lines' blend and linear post-processing (makeLinearAlong
/// with its default reach, plus the kernel's 5σ) may change: within max(lineBlendReach,
/// (LinearityOptions::reach + 5)·σ) of a line. Sorted.
std::vector<Index> lineNeighbourhoodRows(const Cage& cage, std::span<const StructureLine> lines, const Points& X,
                                         double sigma);

}  // namespace kc
