#pragma once
/// The bind pipeline: cage → samples → K → W0 → W → coordinate field (ARCHITECTURE.md data flow).

#include <atomic>
#include <exception>
#include <functional>
#include <span>
#include <vector>

#include "kc/app/session.h"

namespace kc::app {

struct BindReport {
  sampling::SamplingReport sampling;
  InterpolatorReport factor;
  InitReport init;
  OptimizeReport optimize;
  double solveSeconds = 0.0;   ///< U (and B) from W.
  double totalSeconds = 0.0;
};

/// Progress of a bind: stage name and fraction in [0, 1]. Return false to cancel.
using BindProgress = std::function<bool(const char* stage, double fraction)>;

/// Thrown by bind() when its progress callback asked to cancel.
class BindCancelled : public std::exception {
 public:
  const char* what() const noexcept override { return "bind cancelled"; }
};

/// Automatic sampling margin in `thesis` interpolation mode, in sample spacings (the exact mode
/// uses the sampler's default of about 3h). Measured on the checker cage, which spans its whole
/// image, at h = 8: partition-of-unity error 1.2e-2 with ~3h, 3.0e-3 with 5h, 1.3e-3 with 10h.
inline constexpr double kThesisMarginSpacings = 10.0;

/// Largest image side bind() accepts, in pixels.
inline constexpr int kMaxImageSide = 32768;

/// Estimate of the automatic σ before sampling: 3T/π (thesis 3.28) with T = h. bind() itself
/// uses the measured mean nearest-neighbour spacing of the samples (sampling::suggestSigma).
double automaticSigma(double spacing);

/// Binds a cage over an image of width×height pixels. Throws std::invalid_argument for bad input
/// (invalid cage, bad parameters, too many samples) and std::runtime_error when the kernel matrix
/// cannot be factorized (with the advice of the report).
Session bind(const Cage& cage, int width, int height, const BindParams& params, BindReport* report = nullptr,
             const BindProgress& progress = {});

/// Re-optimizes rows `subset` of session.W (all when empty) from session.W0 with `method`, then
/// refreshes the coordinate field, re-solving only the columns of W that changed (all of them when
/// the subset is empty). `changedColumns`, when given, receives those columns. Returns the
/// optimizer's report.
OptimizeReport reoptimize(Session& session, Method method, std::span<const Index> subset = {},
                          std::vector<Index>* changedColumns = nullptr);

/// Rebuilds session.field from samples, σ and W (after loading a session file).
InterpolatorReport refreshField(Session& session);

}  // namespace kc::app
