#pragma once
/// Lifting the kernel field's negative lobes inside the cage.
///
/// The QP (4.1) keeps the data weights W ≥ 0 at the samples, but the kernel interpolant between
/// them undershoots where a weight's data kink (where it falls to 0, and at the cage's vertices,
/// where the edges' hat functions kink): lobes of −0.03 to −0.1 a spacing past the kink, which a
/// drag moves against its direction. The lift adds to the kernel coefficients U a sparse ΔU whose
/// rows are orthogonal to [1 x y] of the controls,
///
///   w(x) ← w(x) + k(x)ᵀΔU,   ΔU·1 = 0,   ΔU·C = 0   (C the m×2 control points),
///
/// so partition of unity and reproduction hold exactly, as before, everywhere. Each deepest point y
/// of a lobe of control j (found from probes half a spacing around every sample inside the cage
/// and along the cage's loop edges, a quarter spacing apart, then a pattern search) gets the bump
/// t·(Σ_i c_i k(x, x_i))·d over the samples x_i whose kernels reach y, with
///
///   d = e_j − A G (GᵀAG)⁻¹ Gᵀe_j,   G = [1 C],   A = diag(min(max(w(y), 0), 10ε) + ε),
///
/// the least change in the QP's allowance metric (optimizer.h, kAllowanceCap) that raises w_j and
/// keeps the constraints: the controls that are large at y give the weight back. c is the kernel
/// row k(y, x_i) made orthogonal to the kernel rows of the control points it reaches, so w(c_p) =
/// e_p stays exact (thesis 3.18), and t sets w_j(y) to the target. Each round re-probes within a
/// few spacings of its lobes. The bump is a sum of the field's own kernels, so the lifted field is
/// as smooth as before; it no longer interpolates W at the samples near a lobe (by ~0.01–0.05).

#include "kc/core/cage.h"
#include "kc/core/field/kernel_field.h"
#include "kc/core/types.h"

namespace kc {

struct LobeLiftOptions {
  /// Lobes deeper than −trigger are lifted.
  double trigger = 0.014;
  /// The value a lifted lobe's deepest point is given: a lift to 0 raises the lobe's flanks above
  /// the drag area's threshold (0.0125) on the side of the weight's support.
  double target = -0.012;
  /// ε of the metric that shares the lift's counterweight among the controls (kQpAllowance).
  double allowance = 0.005;
  /// Rounds of probing and lifting (a lift can leave a shallower lobe on its flank).
  int rounds = 3;
};

struct LobeLiftReport {
  Index lobes = 0;           ///< Lobes lifted, over all rounds.
  int rounds = 0;            ///< Rounds that found lobes.
  double deepestBefore = 0;  ///< Deepest weight found at the probes before the lift.
  double deepestAfter = 0;   ///< Deepest weight at the last round's probes.
  double seconds = 0.0;
};

/// Lifts the lobes of `field` (ready; its samples with kinds `kinds`, the first m the controls)
/// inside `cage`: adds the lift to the field (KernelField::addLift). The bumps vanish at the
/// control points (the Lagrange property stays exact); a lobe they pin all round stays.
LobeLiftReport liftLobes(KernelField& field, const Cage& cage, const std::vector<SampleKind>& kinds,
                         const LobeLiftOptions& options = {});

}  // namespace kc
