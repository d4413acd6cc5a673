#pragma once
/// What the GUI shows of the bound session, made once from it when a bind, an opened session or a
/// job's result is installed (AppState::bound). A job borrows the session (AppState::session is
/// null meanwhile), so the canvas and the panels draw from this snapshot, never from the session.
/// Immutable: a change of the session is a new snapshot.

#include <memory>
#include <vector>

#include "kc/app/backend.h"
#include "kc/app/session.h"

namespace kc::ui {

/// A line drawn deformed with the pose: points X (#n×2, along the line) and their weights W (#n×m).
struct BoundLine {
  Points X;
  Weights W;
  int group = -1;  ///< The parallel group of a structure line (−1: none; rigid outlines: −1).
};

struct BoundSnapshot {
  Cage cage;
  SampleSet samples;
  /// The local spacing h(x) at each sample (#S; `spacing` everywhere when uniform): the sample
  /// plot's colours.
  Eigen::VectorXd sampleSpacing;
  double spacing = 0.0;     ///< The sample spacing h (pixels).
  double minSpacing = 0.0;  ///< The smallest local spacing (the sizing field's; == spacing when uniform).
  /// The kernel width σ where the spacing is `spacing` (pixels; smaller in proportion where the
  /// spacing is); 0 when the weights have no kernel (LBC).
  double sigma = 0.0;
  Method method = Method::QP;  ///< The current optimization method.
  /// What the session's backend can do (greys out the rest, with capabilities.why as tooltip).
  app::BackendCapabilities capabilities;
  app::BindReport report;  ///< The bind's report (app::Session::report).
  /// The structure lines: each line's sample positions (a → b) and their weights, or with exact
  /// lines its two ends and the field's weights there. Empty without lines.
  std::vector<BoundLine> lines;
  /// The rigid regions' polygons (structure.rigid) as outlines: 16 points per edge and the field's
  /// weights there.
  std::vector<BoundLine> rigidOutlines;
  std::vector<double> rigidity;  ///< Per-sample rigidity ρ (#S, or empty: none).
};

/// The snapshot of `session` (which must be bound: cage, samples, W and field). With `previous` (the
/// snapshot of the same bind before a job: a stroke, a method switch, a rigidity stroke), its
/// samples and their spacings are taken over when the session's samples are still those.
std::shared_ptr<const BoundSnapshot> makeBoundSnapshot(const app::Session& session, const BoundSnapshot* previous = nullptr);

}  // namespace kc::ui
