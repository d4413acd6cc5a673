#pragma once
/// The weights of the exterior samples next to a closed cage, continued from the inside.
///
/// A kernel field interpolates its samples' weights; across a cage edge it sees the inside rows
/// (heat targets optimized with w ≥ 0) and the exterior rows (diffused outside, and outside the
/// control points' hull forced by reproduction towards the hull's vertices). Where the two differ
/// in slope the interpolant rings, and the ring reaches inside the cage as negative lobes (−0.135
/// on the bundled figure next to the elbow: exterior samples above the arm carry 0.8 of the hand's
/// weight, the inside ones 0.1, the edge between them 0).
///
/// The continuation replaces each such exterior row by the odd reflection of the inside through
/// the cage: for an exterior sample x at distance d < band from the cage, with p its nearest
/// point on a loop edge (a, b) and λ(p) the edge's linear weights there (4.7), and m = 2p − x its
/// mirror image inside the cage,
///   w(x) = α(d) · (2 λ(p) − ŵ(m)) + (1 − α(d)) · w_opt(x),   α(d) = 1 − smoothstep(d / band),
/// where ŵ(m) is a moving-least-squares fit (linear basis, Gaussian weights) of the rows of the
/// samples inside and on the cage around m, and w_opt(x) the row the optimizer gave x. Each term
/// sums to 1 and reproduces its position (the fit reproduces affine data exactly, and 2p − m = x),
/// so the result keeps partition of unity and reproduction exact; it may be negative outside.
/// Rows whose mirror falls outside the cage (past a thin part) keep w_opt, and so do rows in a gap
/// narrower than the band: α is multiplied by smoothstep((d + d′)/band − 1), d′ the distance to the
/// other side (another loop edge seen across the outside, or a stick; on a closed polygon only a
/// wall the cage reaches from this one by turning 60° or more towards the outside, a pocket such
/// as a gap between legs, not the far side of a convex part such as a foot), because continuing either
/// side into a narrow gap would steepen the weights across it, and a stick's linear weights are
/// the data next to it.
///
/// A gap or an outside wedge between two loop walls that a graded sampling refines (narrower
/// than outsideNarrowWidth·hMax, SizingOptions: a few samples across) holds both sides: there
/// the row blends the two walls' reflections R (this side, at distance d) and R′ (the other side,
/// at d′),
///   w(x) = γ·((1 − s)·R + s·R′) + (1 − γ)·(the single-side rule above),
///   s = smoothstep((u − 0.2)/0.6),  u = d/(d + d′) ∈ [0, 1/2],
/// γ = ρ·(1 − smoothstep((d + d′)/band − 2)),
/// ρ = 1 − smoothstep(2·((d + d′)/hMax − n)) (1 up to the refined width n·hMax, 0 half an hMax
/// wider; n = ExteriorContinuationOptions::blendWidth, the sizing's outsideNarrowWidth). The fifth
/// of the gap next to each wall continues that wall alone, so the inside next to a wall sees its
/// own side's field continued, not a ramp towards the far side's (the leak across a gap
/// kFeatureSamples quotes); the blend is C¹ in u and symmetric
/// (s(1/2) = 1/2), and keeps partition of unity and reproduction exact as each R does. A wider gap,
/// and every gap of a uniform sampling, keeps the single-side rule.

#include <memory>
#include <span>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/sizing.h"
#include "kc/core/types.h"

namespace kc {

struct ExteriorContinuationOptions {
  /// Width of the band, in local sample spacings h(x): beyond it the optimizer's rows are kept.
  /// 2 left the shallowest negative weights inside the cage (docs/notes/measured-constants.md).
  double bandSpacings = 2.0;
  /// Radius of the inside fit around m, in local spacings (grown until it holds 3 points off one line).
  double fitSpacings = 2.0;
  /// n of ρ (see above), in units of hMax: the width below which the sampling's sizing refined a gap
  /// between two parts (SizingOptions::outsideNarrowWidth of the sizing the samples were placed by).
  /// A wider gap holds too few samples across for the two-sided blend, and keeps the single-side rule.
  double blendWidth = kOutsideNarrowWidth;
};

/// The exterior samples the continuation replaces and how: for each, the mirror fit and blend.
/// Built once per sampling (positions, kinds, cage and spacing); applied to any W.
class ExteriorContinuation {
 public:
  ExteriorContinuation() = default;
  /// S: the samples (kinds Exterior are continued, Control/Edge/Interior/Line are the inside);
  /// spacing: h away from narrow places; sizing: the local spacing of a graded sampling (null:
  /// uniform). A cage without an interior (sticks only) continues nothing.
  ExteriorContinuation(const SampleSet& S, const Cage& cage, double spacing, const SizingField* sizing,
                       const ExteriorContinuationOptions& options = {});

  /// The exterior rows continued (increasing).
  const std::vector<Index>& rows() const { return m_rows; }
  /// The inside rows row k's fit reads (increasing).
  std::vector<Index> sources(std::size_t k) const;

  /// Overwrites rows() of W (#S×m), whose rows hold the optimizer's weights, with the continued
  /// weights (see the file comment). Reads only the inside rows of W and the continued rows'
  /// own. Parallel over rows, bit-identical for any thread count.
  void apply(Weights& W) const;
  /// The same for the continued rows in `only` (increasing, each one of rows()).
  void apply(Weights& W, std::span<const Index> only) const;

 private:
  struct Reflection {
    double c = 0.0;             // its share of the row
    int a = -1, b = -1;         // edge end controls (a == b: the nearest point is a control)
    double t = 0.0;             // p = (1 − t)·c_a + t·c_b
    std::vector<Index> fitRows; // inside samples of the fit
    std::vector<double> fit;    // their MLS shape-function values at m (sum 1, reproduce m)
  };
  struct Term {
    Index row = 0;              // the exterior sample
    double keep = 0.0;          // the share of its optimized row
    std::vector<Reflection> reflections;
  };
  std::vector<Term> m_terms;
  std::vector<Index> m_rows;
};

}  // namespace kc
