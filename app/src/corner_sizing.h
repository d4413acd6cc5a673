#pragma once
// Refinement of the sizing field at the cage's sharp outside corners (private to app).

#include <vector>

#include "kc/core/cage.h"
#include "kc/core/sizing.h"

namespace kc::app {

/// Outside corners sharper than this are refined (an armpit, a crotch, the root of a thumb).
inline constexpr double kSharpCornerDegrees = 60.0;
/// The refinement's finest spacing, as a fraction of hMax. Finer corners sharpen the weights'
/// turn there: at hMax/3 the bundled figure's demo pose folds a triangle at the armpit.
inline constexpr double kSharpCornerFinest = 0.5;

/// Samples across the outside wedge of a sharp corner (its k): finer corners sharpen the weights'
/// turn there, as kSharpCornerFinest says.
inline constexpr double kSharpCornerSamples = 2.0;

/// h with seeds (p_i, h_i) added along both edges of every sharp outside corner of a closed
/// polygon cage: where two edges meet at a reflex vertex with an angle θ < kSharpCornerDegrees
/// between them, a point at distance s from the corner along one edge lies s·sin θ from the other,
/// the width of the outside wedge there; it gets h = clamp(s·sin θ / k, kSharpCornerFinest·hMax,
/// hMax) with k = kSharpCornerSamples, seeds every h/2 until h reaches hMax. featureSizing
/// counts the gap between two edges only when they share no end; at a sharp corner they do, and
/// the kernel, which is Euclidean, otherwise reaches across the wedge from one side to the other
/// (negative lobes inside next to it: −0.13 at the bundled figure's armpits). h itself, in its
/// form, for an edge graph (sticks) or a cage without such a corner.
SizingField withSharpCorners(const Cage& cage, const SizingOptions& options, const SizingField& h);

}  // namespace kc::app
