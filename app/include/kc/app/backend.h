#pragma once
/// Weight backends: how a bind turns (cage, image size, parameters) into a coordinate field, and
/// what the result can do afterwards (BackendCapabilities, sessionCapabilities). docs/ARCHITECTURE.md,
/// "Backends", lists where code still compares a backend's name.

#include <exception>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "kc/core/cancel.h"
#include "kc/app/session.h"
#include "kc/core/structure/linear_along.h"
#include "kc/core/structure/rigidity.h"

namespace kc::app {

/// What one bind did, stage by stage (the solver outcomes are also kept in Session::reports).
struct BindReport {
  sampling::SamplingReport sampling;
  InterpolatorReport factor;
  InitReport init;
  OptimizeReport optimize;
  double solveSeconds = 0.0;   ///< Coefficients of the field from W (and the lines' post-processing).
  LinearityReport lines;       ///< Structure lines (thesis 5.3.3); empty without lines.
  RigidityReport rigidity;     ///< Rigid regions (thesis 5.4, docs/rigidity.md); empty without them.
  double totalSeconds = 0.0;
};

/// Announces a bind stage (name, fraction in [0, 1]); throws kc::Cancelled when asked to stop.
using BindStep = std::function<void(const char* stage, double fraction)>;

/// What a backend's sessions can do. A missing capability comes with the reason the GUI shows.
struct BackendCapabilities {
  bool targets = false;      ///< Per-sample target weights W0 exist (weights.initial).
  bool methods = false;      ///< The per-sample optimization method can be switched after a bind.
  bool painting = false;     ///< The brush paints targets and re-optimizes the painted samples.
  bool outsideCage = false;  ///< The field has weights outside the cage (`--outside deform`).
  bool lines = false;        ///< Structure lines kept straight and parallel (`--structure` "lines", thesis 5.3).
  bool rigidity = false;     ///< Rigid regions (`--structure` "rigid", the rigidity brush; thesis 5.4).
  std::string why;           ///< Why the missing capabilities are missing (tooltip text).
};

class Backend {
 public:
  virtual ~Backend() = default;
  /// The name in params.backend and `--backend`.
  virtual std::string_view name() const = 0;
  virtual BackendCapabilities capabilities() const = 0;
  /// Fills everything of `s` a bind computes: samples, σ, W0 (when the backend has targets), W, the
  /// field and s.reports. s.cage, s.params and the image size are set; `step` reports progress
  /// (and throws kc::Cancelled). Throws std::invalid_argument for parameters the backend rejects.
  virtual void bind(Session& s, BindReport& report, const BindStep& step) const = 0;
  /// Rebuilds s.field from what a session file holds (samples, W, params, the field block already
  /// parsed into s.field when it was self-contained). Throws InputError-worthy
  /// std::invalid_argument with the reason when the field cannot be rebuilt.
  virtual void rebuildField(Session& s) const = 0;
  /// Re-optimizes rows `subset` of s.W (all when empty) from s.W0 with `method` and updates the
  /// field's changed columns (returned in changedColumns). Only for backends with `methods`.
  virtual OptimizeReport reoptimize(Session& s, Method method, std::span<const Index> subset,
                                    std::vector<Index>* changedColumns) const = 0;
};

/// The backend called `name`; throws std::invalid_argument naming the available ones.
const Backend& backendFor(std::string_view name);
/// Names of every available backend ("kc", "lbc").
std::vector<std::string_view> backendNames();
/// Capabilities of a bound session: its backend's, less what the session lacks (no
/// weights.initial → no targets, painting or method switches).
BackendCapabilities sessionCapabilities(const Session& s);
/// What of `structure` a backend with `caps` cannot keep: "lines", "rigid regions", "lines and rigid
/// regions", or "" when it keeps all of it. `paintedRigidity`: rigid parts held besides the
/// structure's regions (the GUI's rigidity brush) count as rigid regions.
std::string unsupportedStructure(const Structure& structure, const BackendCapabilities& caps, bool paintedRigidity = false);
/// `structure` without what a backend with `caps` cannot keep (its lines and groups, its rigid regions).
Structure keptStructure(Structure structure, const BackendCapabilities& caps);
/// The refusal of `structure` by `backend` ("lines are not supported by the 'lbc' backend (use
/// --backend kc)"), or "" when the backend keeps all of it.
std::string structureRefusal(const Structure& structure, const Backend& backend);

}  // namespace kc::app
