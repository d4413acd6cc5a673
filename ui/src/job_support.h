#pragma once
// What the worker jobs of jobs.cpp and rigidity_edits.cpp share: borrowing the session and the
// display mesh's weight source, and handing them back. Private to kc::ui's sources; main thread
// unless noted.
#include <chrono>
#include <memory>
#include <string>

#include "kc/app/session.h"
#include "kc/ui/app_state.h"

namespace kc::ui::detail {

using SessionPtr = std::shared_ptr<app::Session>;
using MeshPtr = std::shared_ptr<WarpMesh>;
using SourcePtr = std::shared_ptr<AppState::MeshSource>;

/// Milliseconds since t0 (any thread).
double msSince(std::chrono::steady_clock::time_point t0);

/// A stroke's (or a method switch's) job has its result, started at t0 (its release): records the
/// job's share of timings.releaseToPictureMs; the window completes it after the frame that shows it.
void noteReleaseResult(AppState& state, std::chrono::steady_clock::time_point t0);

/// Installs a new display mesh (after a weight change; none when `mesh` is null) and hands the
/// session and the mesh's weight source back; refreshes the display copies (method, reports,
/// lines, rigidity).
void takeBack(AppState& state, SessionPtr session, const MeshPtr& mesh, SourcePtr source);

/// A closure that hands the session (and the borrowed mesh source) back and reports `text` as an error.
Worker::Apply failure(SessionPtr session, std::string text, SourcePtr source = nullptr);

/// Restores the session's field and the vertex weights from W after a failed job (they may be
/// half updated). Worker thread.
void rebuildFromW(app::Session& s, AppState::MeshSource& source);

/// False (with a "Busy: <what> after the current job has finished." message) while a job runs.
bool canStart(AppState& state, const char* what);

}  // namespace kc::ui::detail
