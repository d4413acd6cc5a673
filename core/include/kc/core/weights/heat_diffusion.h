#pragma once
/// Initial (target) weights W0 (thesis 4.6): inverse squared distance (4.10) and heat diffusion
/// with impulse initialization (4.11–4.12) or with fixed linear weights on edges (4.13).

#include "kc/core/cage.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc {

enum class InitMethod {
  HeatLinear,       ///< Heat diffusion, edge samples fixed to their linear weights (4.13). Default.
  HeatImpulse,      ///< Heat diffusion from Dirac deltas at the control points (4.11–4.12).
  InverseDistance,  ///< w_ij = 1 / (1 + (|x_j − c_i| / p)²) (4.10).
};

struct InitOptions {
  InitMethod method = InitMethod::HeatLinear;
  /// Diffusion iterations; 0 = the converged steady state solved directly (HeatLinear only).
  int iterations = 0;
  /// p of (4.10), in the units of X; ≤ 0 picks a tenth of the cage's bounding-box diagonal.
  double inverseDistanceP = 0.0;
};

struct InitReport {
  int iterations = 0;
  bool steadyState = false;
  double seconds = 0.0;
};

/// W0 (#S×m). Control samples get e_i (3.18), edge samples the linear weights of (4.7) in the
/// HeatLinear variant. Diffusion uses K with each row normalized to sum 1, restricted to pairs of
/// samples whose connecting segment does not cross the cage, so heat never jumps between the
/// inside and the outside (edge samples are the shared boundary).
Weights initialWeights(const SampleSet& S, const Cage& cage, const SparseMatrix& K, const InitOptions& options,
                       InitReport* report = nullptr);

}  // namespace kc
