#pragma once
/// One entry point for sampling a cage and its image domain (what `bind` and `sample` call).

#include <cstdint>
#include <functional>
#include <string>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc::sampling {

enum class SamplerKind { BlueNoise, Grid };

/// Upper bound on the number of samples of one sampling: beyond it `sample` throws
/// std::invalid_argument naming the spacing that would fit.
inline constexpr Index kMaxSamples = 400000;

struct SamplingOptions {
  double spacing = 6.0;      ///< h: sample spacing in pixels (> 0).
  double width = 0.0;        ///< Image domain [0, width] × [0, height] in pixels.
  double height = 0.0;
  /// Margin around the image (pixels); < 0 = automatic (a few σ ≈ 3h, so coordinates stay
  /// accurate up to the image border, thesis Fig 3.1).
  double margin = -1.0;
  SamplerKind kind = SamplerKind::Grid;
  std::uint64_t seed = 1;
  /// Progress callback for long relaxations (fraction in [0, 1]); may be empty.
  std::function<void(double)> progress;
};

struct SamplingReport {
  Index controls = 0, edge = 0, interior = 0, exterior = 0, frame = 0;
  int iterations = 0;        ///< Relaxation iterations (blue noise).
  double seconds = 0.0;
};

/// Samples: control points first (0..m−1, thesis 3.18), then every cage edge at a common
/// spacing ≈ h (kind Edge, with its edge's ends), then free samples covering the domain plus
/// margin, each labelled Interior or Exterior and kept at least h/2 away from edge samples.
/// Throws std::invalid_argument for spacing ≤ 0, non-finite input, or a count above kMaxSamples.
SampleSet sample(const Cage& cage, const SamplingOptions& options, SamplingReport* report = nullptr);

}  // namespace kc::sampling
