#pragma once
/// Inverse mean shift relaxation of free samples among fixed ones (thesis 6.2.1, eq. 6.4).

#include <functional>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/sizing.h"
#include "kc/core/solve.h"
#include "kc/core/types.h"
#include "kc/sampling/boundary.h"

namespace kc::sampling {

struct InverseMeanShiftOptions {
  double spacing = 0.0;        ///< h: target spacing (> 0).
  double scale = -1.0;         ///< s of (6.4); < 0 → 0.6 h.
  double step = -1.0;          ///< λ of (6.4); < 0 → 0.3 s².
  double cutoff = 3.0;         ///< Neighbours within cutoff · s contribute.
  double maxMove = 0.25;       ///< Largest move per iteration, fraction of h (stability cap).
  double tolerance = 3e-3;     ///< Stop when the largest move < tolerance · h.
  int maxIterations = 1000;
  double clearance = 0.35;     ///< A free sample stays this far (· h) from the cage and the domain boundary.
  /// Called after every iteration with an estimate of the fraction done (non-decreasing, the
  /// larger of the iteration budget used and the log-scale progress of the largest move towards
  /// the tolerance), and with 1 at the end. Returning false throws kc::Cancelled (outside parallel
  /// loops; the callback may also throw).
  Progress progress;
  /// Graded sampling: when set and graded(), each sample k relaxes at its local spacing
  /// h_k = (*sizing)(x_k) instead of `spacing` (which is then sizing->hMax()): the pair k, j uses
  /// the bandwidth s·h_kj/h with h_kj² = (h_k² + h_j²)/2 (symmetric: the forces balance, which the
  /// relaxation needs to settle), and the move cap, tolerance and clearance of k scale with h_k. The step (6.4) is
  /// scale-free (λ/s² = 0.3 by default), so a locally uniform region relaxes as a uniform one.
  /// h_k is re-evaluated only after x_k has moved 0.1·h_k since it was last (h is g-Lipschitz: it
  /// is then within 0.1·g of the exact value, 3% at g = 0.3).
  const SizingField* sizing = nullptr;
};

struct InverseMeanShiftReport {
  int iterations = 0;
  bool converged = false;
  double lastMove = 0.0;       ///< Largest move of the last iteration / h (graded: / the sample's own h).
  std::vector<double> largestMoves;  ///< Largest move / h of every iteration (convergence plot).
  Index rejectedMoves = 0;     ///< Moves refused (would leave the region or cross the cage).
  double seconds = 0.0;
};

/// Where free samples may go. A move is refused when it comes closer than clearance·h to the
/// cage (so it can neither cross it nor touch it) or to the domain's boundary. With `periodic`
/// the domain is a torus instead (no cage; used for blue noise in a rectangle).
struct RelaxRegion {
  const Cage* cage = nullptr;  ///< May be null (no cage).
  Rect domain;
  bool periodic = false;
};

/// Relaxes rows [firstFree, #X) of X (#X×2) by inverse mean shift (6.4):
///   x_k ← x_k + λ Σ_j (x_k − x_j) / s² · G_s(x_k − x_j),  G_s(d) = exp(−|d|² / 2s²),
/// summing over all samples j within r = cutoff·s, with G_s(d) − G_s(r) in place of G_s so the
/// sum is continuous at the cut-off. Neighbours come from a SpatialGrid (O(n) per iteration); off
/// the torus, each free sample keeps a list of the samples within about 1.2 r of it, rebuilt from
/// the grid only after some sample has moved 0.15 of its spacing (or its spacing grew 5%) since;
/// rows [0, firstFree) are fixed. Jacobi updates (new positions from old ones, each sample
/// writing its own row): bit-identical for any thread count. Stops when the largest move falls
/// below tolerance·h or after maxIterations.
InverseMeanShiftReport relaxInverseMeanShift(Points& X, Index firstFree, const RelaxRegion& region,
                                             const InverseMeanShiftOptions& options);

}  // namespace kc::sampling
