#pragma once
/// Initial (target) weights W0 (thesis 4.6): inverse squared distance (4.10) and heat diffusion
/// with impulse initialization (4.11–4.12) or with fixed linear weights on edges (4.13).

#include <optional>

#include "kc/core/cage.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc {

enum class InitMethod {
  HeatLinear,       ///< Heat diffusion, edge samples fixed to their linear weights (4.13). Default.
  HeatImpulse,      ///< Heat diffusion from Dirac deltas at the control points (4.11–4.12).
  InverseDistance,  ///< w_ij = 1 / (1 + (|x_j − c_i| / p)²) (4.10).
  /// Local barycentric coordinates at the samples inside the cage (solved on a mesh of the cage
  /// interior, core/lbc), HeatLinear outside. Not computed by initialWeights: the caller runs it
  /// with HeatLinear and overwrites the rows inside the cage (app/src/kc_backend.cpp).
  Lbc,
};

template <>
struct EnumNames<InitMethod> {
  static constexpr std::array<std::pair<InitMethod, std::string_view>, 4> table{
      {{InitMethod::HeatLinear, "heat-linear"},
       {InitMethod::HeatImpulse, "heat-impulse"},
       {InitMethod::InverseDistance, "inverse-distance"},
       {InitMethod::Lbc, "lbc"}}};
};

struct InitOptions {
  InitMethod method = InitMethod::HeatLinear;
  /// Diffusion iterations (4.12, 4.13); 0 = the converged steady state solved directly:
  /// (D_FF − K_FF) W_F = K_FB W_B, one sparse SPD solve with m right-hand sides. For HeatImpulse
  /// the steady state is the same system with only the control points fixed.
  int iterations = 0;
  /// p of (4.10), in the units of X; ≤ 0 picks a tenth of the cage's bounding-box diagonal.
  double inverseDistanceP = 0.0;
  /// Locality length ℓ (units of X, finite and > 0) of HeatLinear's steady state; none (default) =
  /// the unscreened steady state of (4.13) (harmonic-like, smooth, monotone, global weights). A
  /// length solves the screened diffusion ((1+μ)D − K) W = …, in which heat from an edge decays
  /// like exp(−d/ℓ) with the distance d travelled inside the shape, normalizes each row to sum 1,
  /// and then moves each free row to reproduce its position with corrections proportional to its
  /// own targets (min Σ (w_i − w0_i)²/w0_i s.t. Cw = x, 1ᵀw = 1, w ≥ 0), so the per-sample QP
  /// leaves it as is inside the control hull. More local weights, but reproduction still recruits
  /// extreme controls a little far away (a faint, non-monotone halo ~1e-2). Ignored by the other
  /// methods. initialWeights throws std::invalid_argument for a length that is not finite and > 0.
  std::optional<double> locality;
};

/// A locality length as a fraction of the cage's bounding-box diagonal (≈ 25 px on the bundled
/// 320×400 figure): the "automatic" length of kcwarp's `--locality -1`.
inline constexpr double kAutoLocalityFraction = 0.05;

/// The bounding-box locality length for control points C: kAutoLocalityFraction of their
/// bounding-box diagonal.
double automaticLocality(const Points& C);

struct InitReport {
  int iterations = 0;
  bool steadyState = false;
  /// Free samples with no path (inside the shape) to a fixed sample: they get (4.10) weights
  /// normalized to sum 1 instead of diffused ones.
  Index fallbackSamples = 0;
  /// Samples whose screened heat underflowed to nothing (the screening was too strong for them):
  /// each of those rows is the unscreened steady state instead; the other rows stay screened.
  Index unscreenedSamples = 0;
  double seconds = 0.0;
};

/// W0 (#S×m). Control samples get e_i (3.18), edge samples the linear weights of (4.7) in the
/// HeatLinear variant. Diffusion uses K with each row normalized to sum 1, restricted to pairs of
/// samples whose connecting segment does not cross the cage, so heat never jumps between the
/// inside and the outside (edge samples are the shared boundary). The operator is also directed:
/// inside and on-cage samples take heat only through segments inside (or along) the cage, exterior
/// samples from exterior and on-cage ones, so heat cannot leave at one wall of a notch and re-enter
/// at the other. The steady state (iterations = 0, the default) is a partition of unity in [0, 1]
/// reaching every sample; a few iterations leave most samples with row sums ≪ 1. S.X rows 0..m−1 are the
/// controls; cage.C supplies the edge ends of (4.7). Throws std::invalid_argument on bad shapes
/// and for InitMethod::Lbc (solved by the caller on a mesh of the cage).
Weights initialWeights(const SampleSet& S, const Cage& cage, const SparseMatrix& K, const InitOptions& options,
                       InitReport* report = nullptr);

/// Sparser targets: in the rows of W0 (#S×m) of the interior and exterior samples of S, every
/// weight w is replaced by max(w − floor, 0) and the row rescaled to sum 1 (a row with no weight
/// above `floor` is left as it is). Controls, edge and line samples keep their exact data. The
/// per-sample optimizer then restores reproduction; what it cannot take back is the diffused
/// heat's long tail, so each control pulls on a smaller part of the shape. floor ≥ 0 (0: no
/// change); throws std::invalid_argument otherwise or when W0 has not #S rows.
void floorTargets(const SampleSet& S, Weights& W0, double floor);

}  // namespace kc
