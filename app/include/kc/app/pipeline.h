#pragma once
/// The bind pipeline: cage → (backend) → coordinate field (ARCHITECTURE.md data flow).

#include <functional>
#include <span>
#include <vector>

#include "kc/app/backend.h"
#include "kc/app/session.h"

namespace kc::app {

/// Progress of a bind: stage name and fraction in [0, 1]. Return false to cancel.
using BindProgress = std::function<bool(const char* stage, double fraction)>;

/// Largest image side bind() accepts, in pixels.
inline constexpr int kMaxImageSide = 32768;

/// Estimate of the automatic σ before sampling: 3T/π (thesis 3.28) with T = h. bind() itself
/// uses the measured mean nearest-neighbour spacing of the samples (sampling::suggestSigma).
double automaticSigma(double spacing);

/// Binds a cage over an image of width×height pixels with the backend params.backend. Throws
/// std::invalid_argument for bad input (invalid cage, bad parameters, unknown backend, too many
/// samples, a kernel matrix that cannot be factorized — with the advice of the report).
Session bind(const Cage& cage, int width, int height, const BindParams& params, BindReport* report = nullptr,
             const BindProgress& progress = {});

/// Re-optimizes rows `subset` of session.W (all when empty) from session.W0 with `method`, then
/// updates the coordinate field's columns that changed (all of them when the subset is empty).
/// `changedColumns`, when given, receives those columns. Returns the optimizer's report. Throws
/// std::invalid_argument when the session's backend cannot re-optimize (sessionCapabilities).
OptimizeReport reoptimize(Session& session, Method method, std::span<const Index> subset = {},
                          std::vector<Index>* changedColumns = nullptr);

/// Rebuilds session.field from what a session file holds (after loading it), through its backend.
void refreshField(Session& session);

}  // namespace kc::app
