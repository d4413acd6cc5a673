#pragma once
// What the worker jobs of jobs.cpp and rigidity_edits.cpp share: borrowing the session and the
// display mesh's weight source, and handing them back. Private to kc::ui's sources; main thread
// unless noted.
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "kc/app/session.h"
#include "kc/ui/app_state.h"
#include "kc/ui/jobs.h"

namespace kc::ui::detail {

using SessionPtr = std::shared_ptr<app::Session>;
using MeshPtr = std::shared_ptr<WarpMesh>;
using SourcePtr = std::shared_ptr<Document::MeshSource>;

/// Milliseconds since t0 (any thread).
double msSince(std::chrono::steady_clock::time_point t0);

/// A stroke's (or a method switch's) job has its result, started at t0 (its release): records the
/// job's share of timings.releaseToPictureMs; the window completes it after the frame that shows it.
void noteReleaseResult(AppState& state, std::chrono::steady_clock::time_point t0);

/// Installs a new display mesh (after a weight change; none when `mesh` is null) and hands the
/// session and the mesh's weight source back, with a new bound snapshot of it (method, reports,
/// lines, rigidity).
void takeBack(AppState& state, SessionPtr session, const MeshPtr& mesh, SourcePtr source);

/// A closure that hands the session (and the borrowed mesh source) back and reports `text` as an error.
Worker::Apply failure(SessionPtr session, std::string text, SourcePtr source = nullptr);

/// Restores the session's field and the vertex weights from W after a failed job (they may be
/// half updated). Worker thread.
void rebuildFromW(app::Session& s, Document::MeshSource& source);

/// False (with a "Busy: <what> after the current job has finished." message) while a job runs.
bool canStart(AppState& state, const char* what);

/// The rigidity painted on the old samples (#S_old), carried over to those of `s` (each takes the
/// ρ of the nearest old sample within max(h_old, h)·1.5) and re-solved on the worker (not recorded).
void carryRigidityTo(AppState& st, const SampleSet& oldSamples, const std::vector<double>& oldRigidity, double oldSpacing,
                     const app::Session& s);

/// Installs the session of a bind that replaces `previous` (rebind.cpp): the pose carries over,
/// painted rigidity is carried to the new samples, and the bind goes on the undo stack (BindEdit).
void installReplacing(AppState& st, SessionPtr previous, std::shared_ptr<app::Session> s, DisplayMesh display);

/// The question before a bind that would leave paint strokes behind ("" when there are none).
std::string rebindQuestion(const Document& doc);

}  // namespace kc::ui::detail
