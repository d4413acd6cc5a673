#pragma once
/// Background jobs on the AppState's worker: bind, re-optimization (strokes, method switch, undo
/// of weights), opening a session, export. A job borrows the session (AppState::session is null
/// meanwhile), works on its own data, and hands everything back in a closure applied on the main
/// thread by pollWorker() — also on failure or cancel, so nothing is lost.

#include <exception>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "kc/app/session.h"
#include "kc/ui/app_state.h"

namespace kc::ui {

/// Sets the outside-the-cage mode (view and export). When a session is bound the display mesh is
/// rebuilt on the worker (the window stays responsive) and the document is marked unsaved.
/// Move everything on a session sampled only in a band around the cage (bandNeedsFrameBind)
/// binds again with the whole picture sampled, keeping the pose; when that would replace unsaved
/// paint strokes (weights, rigidity or a method switch: they cannot be carried over), the
/// unsaved-changes prompt asks first and this returns false. Returns false (with a message)
/// while another job runs.
bool setOutsideMode(AppState& state, OutsideMode mode);

/// True when the bound session was sampled in a band around the cage by a backend that can sample
/// the whole picture: Move everything is offered, through a new bind (setOutsideMode).
bool bandNeedsFrameBind(const Document& doc);

/// The outside mode a session asks for (its "outside" key), or the default.
OutsideMode sessionOutsideMode(const app::Session& session);

/// The parameters the next bind of `cage` over width×height uses: the Bind panel's, sampling the
/// whole picture when the outside mode is Move everything and a band around the cage otherwise
/// (BindParams::exterior), with the automatic spacing when doc.autoSpacing
/// (app::automaticSpacing from the 6 px default).
app::BindParams bindParamsFor(const Document& doc, const Cage& cage, int width, int height);
/// What the next bind of the draft cage uses (Document::ShownSpacing), from the parameters the bind
/// really uses (app::effectiveBindParams of bindParamsFor(doc, doc.cage, picture size) with the
/// draft's lines): their spacing, the smallest spacing of their sizing field (app::bindSizing, lines
/// and rigid polygons included; == spacing for a uniform bind — lines the uniform rules accept
/// keep one — or no narrow place) and the estimated samples (app::estimateBindCost) or, for a mesh backend, mesh vertices
/// (estimateMeshVertices of the uniform mesh; a graded mesh adds some near narrow places).
/// Recomputed only when the draft cage, its lines, the picture size or the parameters it depends
/// on changed since the last call.
const Document::ShownSpacing& spacingPlan(Document& doc);
/// spacingPlan(doc).spacing.
double autoSpacingShown(Document& doc);
/// Kernel widths as shown for a width sigma at `spacing` (σ(x) = σ·h(x)/hMax, kc::GaussianKernel's
/// variable width): "0.44-5.20 px" when minSpacing is smaller, else "5.20 px".
std::string sigmaRangeText(double sigma, double minSpacing, double spacing);
/// The automatic kernel widths the next bind will about use, as shown before it: 3h/π at the
/// planned spacing (spacingPlan), smaller in proportion down to its smallest spacing (Bind measures
/// the spacing on the samples instead of h: app::automaticSigma).
std::pair<double, double> plannedSigma(Document& doc);
/// The bound session's kernel widths as shown (sigmaRangeText); empty when the bound weights have
/// no kernel (LBC) or nothing is bound.
std::string boundSigmaText(const Document& doc);
/// Binds the draft cage with the document's lines (state.lines) over the current image with
/// state.bindParams (progress, Cancel); when it is done the pose tool is active. `markUnsaved` =
/// false for a bind that only reproduces files on disk (the picture and cage given at startup),
/// so an untouched document is not "unsaved". A bind that replaces a bound session keeps the
/// person's work: the pose carries over (carriedPose), painted rigidity is carried to the new
/// samples, the undo history stays and the bind is one entry on it (BindEdit: Ctrl+Z brings the
/// previous session, its weights and pose back). `keepPoseAndHistory` (a re-bind after a line
/// edit, whose undo binds again): the tool and the line selection stay too, there is no BindEdit,
/// and the edits tied to the old samples (paint strokes) leave the history; a cancelled or failed
/// re-bind puts the bound session's lines back and the line edit back on its stack.
/// Returns false (with a message) when the cage is invalid or a job is running.
bool startBind(AppState& state, bool markUnsaved = true, bool keepPoseAndHistory = false);

/// Re-optimizes rows edit.rows (all when empty) of the session from its W0 with edit.methodAfter,
/// refreshes the field and the display mesh; on completion edit.WAfter is filled and pushed to
/// the undo stack as `label`. W0 must already hold edit.W0After. A stroke whose weights would fold
/// the picture under the present pose (more triangles turned over than before it) is halved and
/// re-optimized, up to three times, until it does not (edit.W0After becomes what was kept; the
/// status line says so); one that folds even at an eighth is kept as painted.
bool startReoptimize(AppState& state, WeightEdit edit, std::string label);

/// Re-optimizes all samples from the current targets with `method` (painted targets survive);
/// pushes a MethodEdit when done.
bool switchMethod(AppState& state, Method method);
/// Re-optimizes all samples with `method` on the worker; `record` pushes a MethodEdit when done
/// (undo and redo of a method switch pass false).
bool startMethod(AppState& state, Method method, bool record);

/// Writes W0 rows `rows` and W rows `weightRows` (after undo/redo; empty = all) and refreshes field
/// + display mesh on the worker.
bool startRestoreWeights(AppState& state, const std::vector<Index>& rows, const Weights& W0, const std::vector<Index>& weightRows,
                         const Weights& W,
                         Method method);

/// Loads a session file (and its image) on the worker; on success it replaces the document, on
/// failure the current one is untouched and the error is shown.
bool startOpenSession(AppState& state, const std::string& path);

/// What a failed load or bind reports: e.what() (an app::InputError names the file and the
/// problem), or for std::bad_alloc "<where>: out of memory: <advice>" — and then the memory
/// reserve is set aside again (app::keepMemoryReserve), so that the next failure unwinds as
/// safely as this one did.
std::string failureText(const std::exception& e, const std::string& where, const std::string& advice);

/// Saves the session (with the current pose) atomically on the worker, so a large session does
/// not freeze the window. On success: sessionPath, the unsaved flag (cleared unless the pose
/// changed meanwhile), the recent list, then state.afterSave runs. `autosave` writes the recovery
/// copy instead and changes nothing else. Returns false (with a message) when it cannot start.
bool startSaveSession(AppState& state, const std::string& path, bool autosave = false);

/// Exports the warped picture at full resolution (app::warpSessionImage, as kcwarp-cli warp).
bool startExport(AppState& state, const std::string& path);

/// A display warp mesh and the source of its weights (built on the worker, installed on the main thread).
struct DisplayMesh {
  std::shared_ptr<WarpMesh> mesh;
  std::shared_ptr<Document::MeshSource> source;
};
/// The display mesh of a bound session, keeping the field sampler at its vertices.
DisplayMesh buildDisplayMesh(const app::Session& session, const WarpMeshOptions& options);

/// Makes `session` (bound for `source`) the document: its snapshot (AppState::bound), mesh, pose,
/// undo cleared; the Bind panel takes the session's parameters (graded when it has lines, see
/// jobs.cpp).
/// fromOptimizer: the session's W came from this optimizer (a bind), not from a file.
void installSession(AppState& state, std::shared_ptr<app::Session> session, DisplayMesh display,
                    bool fromOptimizer = false);

/// Applies a finished job's result, if any. Call once per frame on the main thread.
void pollWorker(AppState& state);

/// Runs diagnose() on the session (synchronous; used by the diagnostics panel's Refresh).
void refreshDiagnostics(AppState& state);

}  // namespace kc::ui

#include "kc/ui/rebind.h"  // binding again (requestBind), part of the jobs' interface
