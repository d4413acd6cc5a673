#include "kc/ui/jobs.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>

#include "kc/app/diagnostics.h"
#include "kc/app/export.h"
#include "kc/app/pipeline.h"
#include "kc/app/text.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/ui/edits.h"
#include "kc/ui/line_edits.h"
#include "kc/ui/rigidity_edits.h"
#include "job_support.h"

namespace kc::ui {
namespace detail {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void noteReleaseResult(AppState& state, std::chrono::steady_clock::time_point t0) {
  state.timings.releaseJobMs = msSince(t0);
  state.timings.releaseToPictureMs = state.timings.releaseJobMs;  // until the frame is drawn
  state.releaseStart = std::chrono::duration<double>(t0.time_since_epoch()).count();  // nowSeconds()'s clock
}

void takeBack(AppState& state, SessionPtr session, const MeshPtr& mesh, SourcePtr source) {
  state.session = std::move(session);
  state.bound = makeBoundSnapshot(*state.session, state.bound.get());  // a job keeps its bind's samples
  if (mesh) {
    state.mesh = std::move(*mesh);
    state.meshVersion.bump();
  }
  if (source) state.meshSource = std::move(source);
  state.diagnostics.reset();
}

Worker::Apply failure(SessionPtr session, std::string text, SourcePtr source) {
  return [session, text, source](AppState& st) {
    if (session) st.session = session;
    if (source) st.meshSource = source;
    postMessage(st, text, true);
  };
}

void rebuildFromW(app::Session& s, Document::MeshSource& source) {
  try {
    if (s.field) {
      s.field->update(s.W);
      source.W = source.sampler.evaluate(*s.field);
    }
  } catch (const std::exception&) {
  }
}

/// Posts the solver problems of a bind or re-optimization (warning colour) or nothing.
void postSolverProblems(AppState& st, const OptimizeReport& r, const char* what) {
  if (r.failed == 0) return;
  char text[200];
  std::snprintf(text, sizeof text, "%s: %ld samples not solved to optimality (fallback weights used).", what, long(r.failed));
  postMessage(st, text, true);
}

/// The status line after a bind: what was computed, at how many points, in how long.
std::string bindSummary(const app::Session& s) {
  char text[200];
  if (s.report.backend)
    std::snprintf(text, sizeof text, "Bound %ld control points with %s: %s, %.2f s.", long(s.cage.size()),
                  std::string(app::backendFor(s.params.backend).displayName()).c_str(), s.report.backend->brief().c_str(),
                  s.report.timings.total);
  else
    std::snprintf(text, sizeof text, "Bound %ld control points, %ld samples in %.2f s.", long(s.cage.size()),
                  long(s.samples.size()), s.report.timings.total);
  return text;
}

bool canStart(AppState& state, const char* what) {
  if (state.worker.busy()) {
    postMessage(state, std::string("Busy: ") + what + " after the current job has finished.", false);
    return false;
  }
  return true;
}

}  // namespace detail

using namespace detail;

namespace {

/// After a cancelled or failed re-bind for `tried` lines: the line edit that asked for them goes
/// back to the stack it came from (a new edit or a redo becomes redoable, an undo undoable again).
void restoreLineEdit(AppState& st, const app::Structure& tried) {
  const UndoEntry* u = st.undo.nextUndo();
  const UndoEntry* r = st.undo.nextRedo();
  if (u && std::holds_alternative<LinesEdit>(u->edit) && sameLines(std::get<LinesEdit>(u->edit).after, tried)) st.undo.popUndo();
  else if (r && std::holds_alternative<LinesEdit>(r->edit) && sameLines(std::get<LinesEdit>(r->edit).before, tried)) st.undo.popRedo();
}

/// Edits of the weights that a new bind replaces (the weights are computed anew from the cage).
bool lostByRebind(const UndoEntry& e) {
  if (std::holds_alternative<WeightEdit>(e.edit) || std::holds_alternative<RigidityEdit>(e.edit)) return true;
  const auto* m = std::get_if<MethodEdit>(&e.edit);
  return m && m->WBefore.rows() > 0;
}

/// Installs the session of a re-bind after a line edit, keeping the pose, the tool, the line
/// selection and the undo history without the edits tied to the old samples (paint strokes,
/// weights from a file).
void installKeepingPose(AppState& st, std::shared_ptr<app::Session> s, DisplayMesh display) {
  const Pose pose = st.pose;
  const std::shared_ptr<const BoundSnapshot> before = st.bound ? st.bound : std::make_shared<const BoundSnapshot>();
  const std::vector<double> oldRigidity = boundRigidity(st);
  const Tool tool = st.tool;
  const std::vector<int> selection = st.lineSelection;
  UndoStack history = std::move(st.undo);
  installSession(st, s, std::move(display), true);
  setPose(st, carriedPose(before->cage, pose, s->cage));
  st.tool = tool;
  for (int k : selection)
    if (k < static_cast<int>(st.lines.lines.size())) st.lineSelection.push_back(k);
  const std::size_t dropped = history.removeIf(lostByRebind);
  st.undo = std::move(history);
  if (dropped > 0)
    postMessage(st, "The new bind changed the sampling: the weights were computed anew, and earlier paint strokes (weights and rigidity) can no longer be undone.", false);
  carryRigidityTo(st, before->samples, oldRigidity, before->spacing, *s);
}

}  // namespace

DisplayMesh buildDisplayMesh(const app::Session& session, const WarpMeshOptions& options) {
  DisplayMesh d;
  d.source = std::make_shared<Document::MeshSource>();
  d.mesh = std::make_shared<WarpMesh>(app::buildWarpMesh(session, options, nullptr, &d.source->sampler, &d.source->W));
  return d;
}

void installSession(AppState& state, std::shared_ptr<app::Session> session, DisplayMesh display, bool fromOptimizer) {
  const app::Session& s = *session;
  state.session = std::move(session);
  state.bound = makeBoundSnapshot(s);
  state.solvingRigidity.reset();
  if (state.tool == Tool::Brush && !state.bound->capabilities.painting) state.tool = Tool::Pose;
  if (state.tool == Tool::Rigid && !rigidityProblem(state).empty()) state.tool = Tool::Pose;
  state.bindParams = s.params;
  // Lines the uniform rules accept are sampled uniformly (app::effectiveBindParams), and the session
  // records that; the GUI asks for graded binds, so the line tool and the next bind keep the graded
  // rules (a new line may cross another or end on the cage). The next bind keeps lines straight by
  // the field's exact correction, also for a session bound before it.
  if (!s.structure.lines.empty()) state.bindParams.graded = true;
  state.bindParams.kc.exactLines = true;
  state.lines = s.structure;
  state.lineSelection.clear();
  state.outside = display.mesh->options().outside;
  setDraftCage(state, s.cage);
  setPose(state, s.pose.size() == static_cast<std::size_t>(s.cage.size()) ? s.pose : restPose(s.cage.size()));
  state.mesh = std::move(*display.mesh);
  state.meshSource = std::move(display.source);
  state.meshVersion.bump();
  state.selection.clear();
  state.pivot.reset();
  if (state.activeControl >= s.cage.size() || state.activeControl < 0) state.activeControl = 0;
  state.undo.clear();
  state.diagnostics.reset();
  state.timings.bindSeconds = s.report.timings.total;
  state.weightsReproducible = fromOptimizer;
}

app::BindParams bindParamsFor(const Document& doc, const Cage& cage, int width, int height) {
  app::BindParams params = doc.bindParams;
  params.exterior = app::exteriorFor(doc.outside);
  if (doc.autoSpacing) {
    params.spacing = app::BindParams{}.spacing;  // the budget starts from the default, not the last choice
    params.spacing = app::automaticSpacing(cage, width, height, params);
  }
  return params;
}

const Document::ShownSpacing& spacingPlan(Document& doc) {
  auto& shown = doc.shownSpacing;
  app::BindParams p = doc.bindParams;
  p.exterior = app::exteriorFor(doc.outside);
  if (doc.autoSpacing) p.spacing = 0.0;  // the slider's value is not used
  const auto sameRigid = [](const app::Structure& a, const app::Structure& b) {
    if (a.rigid.size() != b.rigid.size()) return false;
    for (std::size_t k = 0; k < a.rigid.size(); ++k)
      if (a.rigid[k].polygon.rows() != b.rigid[k].polygon.rows() || a.rigid[k].polygon != b.rigid[k].polygon) return false;
    return true;
  };
  const bool same = shown.width == doc.source.width && shown.height == doc.source.height && shown.params.backend == p.backend &&
                    shown.params.sampler == p.sampler && shown.params.margin == p.margin && shown.params.exterior == p.exterior &&
                    shown.params.spacing == p.spacing && shown.params.graded == p.graded && shown.params.kc.sigma == p.kc.sigma &&
                    shown.params.kc.interp == p.kc.interp &&
                    shown.params.kc.init.method == p.kc.init.method &&  // --init lbc samples at half the spacing
                    shown.params.kc.locality == p.kc.locality && shown.params.kc.exactLines == p.kc.exactLines &&
                    shown.closed == doc.cage.closed && shown.cageValid == doc.cageValid &&
                    shown.cage.rows() == doc.cage.C.rows() && shown.cage == doc.cage.C && sameLines(shown.lines, doc.lines) &&
                    sameRigid(shown.lines, doc.lines);
  if (!same) {
    const int w = doc.source.width, h = doc.source.height;
    shown = {doc.cage.C,   w, h, p, doc.lines, doc.bindParams.spacing, doc.bindParams.spacing, 0.0, 0.0, doc.cage.closed,
             doc.cageValid};
    try {  // at the slider's spacing until the bind's is known (below)
      app::BindParams slider = p;
      slider.spacing = doc.bindParams.spacing;
      shown.locality = app::locality(doc.cage, slider).value_or(0.0);
    } catch (const std::exception&) {  // a locality the bind refuses: it says why
    }
    if (doc.cageValid && w > 0 && h > 0) {
      try {
        // The parameters and the sizing field the bind will sample or mesh with (the LBC backend
        // meshes without lines; structure lines may keep the uniform sampling).
        const app::BindParams requested = bindParamsFor(doc, doc.cage, w, h);
        const bool mesh = !app::backendFor(requested.backend).capabilities().outsideCage;
        const app::Structure& structure = mesh ? app::Structure{} : doc.lines;
        const app::BindParams used = app::effectiveBindParams(doc.cage, structure, requested);
        shown.spacing = shown.minSpacing = used.spacing;
        if (const auto sizing = app::bindSizing(doc.cage, structure, used)) shown.minSpacing = sizing->hMin();
        shown.points =
            mesh ? estimateMeshVertices(doc.cage, used.spacing) : app::estimateBindCost(doc.cage, structure, w, h, used).samples;
        shown.locality = app::locality(doc.cage, used, !structure.lines.empty() && !used.kc.exactLines).value_or(0.0);
      } catch (const std::exception&) {
        // A cage or lines the bind refuses: the bind says why; the panel shows the spacing alone.
      }
    }
  }
  return shown;
}

double autoSpacingShown(Document& doc) { return spacingPlan(doc).spacing; }

std::string sigmaRangeText(double sigma, double minSpacing, double spacing) {
  const double smallest = sigma * minSpacing / spacing;
  char text[64];
  if (smallest < sigma - 0.005) std::snprintf(text, sizeof text, "%.2f-%.2f px", smallest, sigma);
  else std::snprintf(text, sizeof text, "%.2f px", sigma);
  return text;
}

std::pair<double, double> plannedSigma(Document& doc) {
  const double spacing = doc.autoSpacing ? autoSpacingShown(doc) : doc.bindParams.spacing;
  const double sigma = app::automaticSigma(spacing);
  if (doc.source.empty() || !doc.cageValid) return {sigma, sigma};
  const Document::ShownSpacing& plan = spacingPlan(doc);
  return {plan.spacing > 0.0 ? sigma * plan.minSpacing / plan.spacing : sigma, sigma};
}

std::string boundSigmaText(const Document& doc) {
  if (!doc.bound || !(doc.bound->sigma > 0.0) || !(doc.bound->spacing > 0.0)) return "";
  return sigmaRangeText(doc.bound->sigma, doc.bound->minSpacing, doc.bound->spacing);
}

bool startBind(AppState& state, bool markUnsaved, bool keepPoseAndHistory) {
  if (!canStart(state, "bind")) return false;
  if (state.source.empty()) {
    postMessage(state, "Open an image before binding.", true);
    return false;
  }
  if (!state.cageValid) {
    postMessage(state, "The cage cannot be bound: " + state.cageStatus, true);
    return false;
  }
  if (!state.worker.canAbandonMore()) {
    postMessage(state, "Busy: cancelled binds are still finishing in the background; bind again in a moment.", false);
    return false;
  }
  SessionPtr previous = std::move(state.session);
  const Cage cage = state.cage;
  const int w = state.source.width, h = state.source.height;
  const app::BindParams params = bindParamsFor(state, cage, w, h);
  // What the backend cannot keep is left out (requestBind asked first); the present bind keeps it.
  const app::Structure lines = app::keptStructure(state.lines, app::backendFor(params.backend).capabilities());
  const app::Structure boundLines = previous ? previous->structure : app::Structure{};
  const std::string narrow =
      app::backendFor(params.backend).narrowPlaceWarning(cage, app::effectiveBindParams(cage, lines, params));
  const std::string image = state.imagePath;
  const bool upright = state.imageUpright;
  WarpMeshOptions meshOptions = app::warpMeshOptionsFor(w, h, app::weightSpacing(params), state.outside);
  if (meshOptions.outside == OutsideMode::Deform && !app::backendFor(params.backend).capabilities().outsideCage) {
    // The backend has no weights outside the cage: the background follows as in the default mode.
    meshOptions.outside = OutsideMode::Pinned;
    postMessage(state, "Outside the cage: Pinned border (Move everything needs weights outside the cage).", false);
  }
  // The kernel factorization and the steady-state heat solve are single solver calls that cannot
  // stop half way, so Cancel abandons the bind (Worker): the previous session comes back at once
  // and the bind's result is dropped when it ends. The job only reads its own copies (cage,
  // params), never `previous`, so handing `previous` back early is safe.
  // A re-bind after a line edit that does not happen leaves the bound session's lines.
  auto restoreLines = [keepPoseAndHistory, lines, boundLines](AppState& st) {
    if (!keepPoseAndHistory) return;
    st.lines = boundLines;
    st.lineSelection.clear();
    restoreLineEdit(st, lines);
  };
  // A bind that does not happen leaves the picture as it was shown, in its outside mode (Move
  // everything chosen on a band session starts a bind: setOutsideMode).
  auto cancelled = [previous, restoreLines](AppState& st) {
    st.session = previous;
    if (previous) st.outside = st.mesh.options().outside;
    restoreLines(st);
    postMessage(st, "Bind cancelled.", false);
  };
  state.worker.submit(
      "Binding",
      [=](JobContext& ctx) -> Worker::Apply {
        try {
          auto s = std::make_shared<app::Session>(
              app::bind(cage, lines, w, h, params, [&](const char* stage, double f) { return ctx.progress(stage, 0.9 * f); }));
          s->image = image;
          s->imageUpright = upright;
          s->outside = meshOptions.outside;
          if (!ctx.progress("warp mesh", 0.92)) throw Cancelled();
          DisplayMesh display = buildDisplayMesh(*s, meshOptions);
          return [s, display, markUnsaved, narrow, keepPoseAndHistory, previous](AppState& st) {
            if (keepPoseAndHistory) {
              installKeepingPose(st, s, display);
            } else if (previous) {
              installReplacing(st, previous, s, display);
            } else {
              installSession(st, s, display, true);
              st.tool = Tool::Pose;
            }
            st.unsaved = st.unsaved || markUnsaved;
            postMessage(st, bindSummary(*s), false);
            if (!narrow.empty()) postMessage(st, "Note: " + narrow + ".", false);
            for (const std::string& p : s->report.problems()) postMessage(st, "Bind: " + p, true);
          };
        } catch (const Cancelled&) {
          return cancelled;
        } catch (const std::exception& e) {
          const std::string text = "Bind failed: " + failureText(e, "",
                                                                 "this cage at this spacing needs more memory than is free; "
                                                                 "use a larger spacing or a smaller picture");
          return [previous, text, restoreLines](AppState& st) {
            if (previous) {
              st.session = previous;
              st.outside = st.mesh.options().outside;
            }
            restoreLines(st);
            postMessage(st, text, true);
          };
        }
      },
      cancelled);
  return true;
}

OutsideMode sessionOutsideMode(const app::Session& session) { return session.outside.value_or(WarpMeshOptions{}.outside); }

bool bandNeedsFrameBind(const Document& doc) {
  if (!doc.bound || !doc.session || doc.session->params.exterior != sampling::ExteriorExtent::Band) return false;
  try {
    return app::backendFor(doc.session->params.backend).capabilities().outsideCage;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

bool setOutsideMode(AppState& state, OutsideMode mode) {
  if (mode == state.outside) return true;
  if (mode == OutsideMode::Deform && bandNeedsFrameBind(state)) {
    // The session's weights reach a band around the cage only: bind again over the whole picture.
    const auto bindAgain = [](AppState& st) {
      const OutsideMode before = st.outside;
      st.outside = OutsideMode::Deform;
      if (!startBind(st)) {
        st.outside = before;
        return false;
      }
      postMessage(st, "Move everything needs weights up to the picture's border: binding again with the whole picture sampled (the pose is kept).", false);
      return true;
    };
    // The new bind computes the weights anew: paint strokes in them are named first.
    if (const std::string question = rebindQuestion(state); !question.empty()) {
      state.unsavedPrompt = PendingAction{"Bind again", [bindAgain](AppState& st) { bindAgain(st); }, question};
      return false;
    }
    return bindAgain(state);
  }
  if (mode == OutsideMode::Deform && !shownCapabilities(state).outsideCage) {
    postMessage(state, "Move everything needs weights outside the cage: " + shownCapabilities(state).why, false);
    return false;
  }
  if (!state.bound) {
    state.outside = mode;
    return true;
  }
  if (!state.session || !canStart(state, "change the outside mode")) return false;
  const OutsideMode before = state.outside;
  state.outside = mode;  // the panel shows the choice while the mesh is rebuilt
  SessionPtr s = std::move(state.session);
  const WarpMeshOptions options = app::warpMeshOptionsFor(*s, mode);
  state.worker.submit("Outside the cage", [s, options, before](JobContext& ctx) -> Worker::Apply {
    try {
      ctx.progress("warp mesh", 0.1);
      const auto t0 = std::chrono::steady_clock::now();
      DisplayMesh display = buildDisplayMesh(*s, options);
      const double ms = msSince(t0);
      return [s, display, ms, mode = options.outside](AppState& st) {
        s->outside = mode;
        takeBack(st, s, display.mesh, display.source);
        st.outside = mode;
        st.unsaved = true;
        st.timings.meshWeightsMs = ms;
      };
    } catch (const std::exception& e) {
      const std::string text = std::string("Changing the outside mode failed: ") + e.what();
      return [s, text, before](AppState& st) {
        st.session = s;
        st.outside = before;
        postMessage(st, text, true);
      };
    }
  });
  return true;
}

namespace {

/// Re-optimizes rows `rows` (all when empty) with `method` on the worker and re-weights the display
/// mesh (only the controls whose weights changed). The session and the mesh's weight source are
/// borrowed by the job (null in the AppState meanwhile) and handed back when it ends. `done` runs
/// on the main thread after success, `undoFailure` on the worker when the optimization threw.
/// A stroke's guard against folds (startReoptimize): when the re-optimized weights fold the picture
/// under `pose` more than `foldsBefore` triangles, the stroke is halved (its targets W0 moved back
/// halfway to W0Before) and re-optimized, up to kStrokeHalvings times; a stroke that still folds
/// then is kept whole (and the fold is told). `kept` is the share of the stroke kept (1, 1/2, …).
struct FoldGuard {
  Pose pose;
  Index foldsBefore = 0;
  Weights W0Before, W0Stroke;  ///< #R×m: the painted rows' targets before and after the stroke.
  double kept = 1.0;
};
constexpr int kStrokeHalvings = 3;

bool submitReoptimize(AppState& state, std::vector<Index> rows, Method method, const char* title,
                      std::function<void(AppState&)> done, std::function<void(app::Session&)> undoFailure,
                      std::shared_ptr<FoldGuard> guard = nullptr) {
  const auto t0 = std::chrono::steady_clock::now();
  SessionPtr s = std::move(state.session);
  SourcePtr source = std::move(state.meshSource);
  auto mesh = std::make_shared<WarpMesh>(state.mesh);  // the worker re-weights a copy
  state.worker.submit(title, [s, source, mesh, rows, method, done, undoFailure, t0, guard](JobContext& ctx) -> Worker::Apply {
    try {
      ctx.progress("optimization", 0.1);
      double reoptimizeMs = 0.0, meshMs = 0.0, setWeightsMs = 0.0;
      OptimizeReport r;
      // Re-optimizes the rows from the session's W0 and re-weights the mesh: only the controls
      // whose weights changed are re-evaluated at the mesh vertices.
      auto solve = [&] {
        const auto t1 = std::chrono::steady_clock::now();
        std::vector<Index> columns;
        r = app::reoptimize(*s, method, rows, &columns);
        reoptimizeMs += msSince(t1);
        const auto t2 = std::chrono::steady_clock::now();
        source->sampler.updateColumns(*s->field, columns, source->W);
        meshMs += msSince(t2);
        const auto t3 = std::chrono::steady_clock::now();
        mesh->setWeights(source->W);
        setWeightsMs += msSince(t3);
      };
      solve();
      ctx.progress("warp mesh", 0.6);
      if (guard && guard->pose.size() == static_cast<std::size_t>(mesh->cage().size())) {
        auto folds = [&] { return mesh->deform(guard->pose, DeformPass::Final).flippedTriangles > guard->foldsBefore; };
        for (int k = 0; k < kStrokeHalvings && folds(); ++k) {
          guard->kept *= 0.5;
          scatterRows(s->W0, rows, guard->W0Before + guard->kept * (guard->W0Stroke - guard->W0Before));
          solve();
        }
        if (guard->kept < 1.0 && folds()) {  // no gentler stroke unfolds it: the stroke as painted
          guard->kept = 1.0;
          scatterRows(s->W0, rows, guard->W0Stroke);
          solve();
        }
      }
      return [s, mesh, source, done, r, reoptimizeMs, meshMs, setWeightsMs, t0](AppState& st) {
        takeBack(st, s, mesh, source);
        st.unsaved = true;
        st.timings.reoptimizeMs = reoptimizeMs;
        st.timings.reoptimizeSamples = r.solved;
        st.timings.meshWeightsMs = meshMs;
        st.timings.meshSetWeightsMs = setWeightsMs;
        if (done) done(st);
        noteReleaseResult(st, t0);
        postSolverProblems(st, r, "Re-optimization");
      };
    } catch (const std::exception& ex) {
      if (undoFailure) undoFailure(*s);
      rebuildFromW(*s, *source);
      return failure(s, std::string("Re-optimization failed: ") + ex.what(), source);
    }
  });
  return true;
}

}  // namespace

bool startReoptimize(AppState& state, WeightEdit edit, std::string label) {
  if (!state.session || !state.meshSource || !canStart(state, "re-optimize")) return false;
  auto e = std::make_shared<WeightEdit>(std::move(edit));
  // W before the stroke, whole: a re-optimization changes the painted rows and the rows derived
  // from them (app::reoptimize), and the undo entry keeps exactly the rows that changed.
  auto before = std::make_shared<const Weights>(state.session->W);
  // A stroke that would fold the shown picture is made gentler (FoldGuard), when the picture shown
  // is the full deform of the present pose.
  std::shared_ptr<FoldGuard> guard;
  if (!e->rows.empty() && state.deformed.current({state.poseVersion, state.meshVersion, false}))
    guard = std::make_shared<FoldGuard>(FoldGuard{state.pose, state.deformReport.flippedTriangles, e->W0Before, e->W0After});
  return submitReoptimize(
      state, e->rows, e->methodAfter, "Re-optimizing",
      [e, label, guard, before](AppState& st) {
        e->W0After = gatherRows(st.session->W0, e->rows);  // the stroke as kept
        const Weights& W = st.session->W;
        e->weightRows.clear();
        for (Index r = 0; r < W.rows(); ++r)
          if (W.row(r) != before->row(r)) e->weightRows.push_back(r);
        e->WBefore = gatherRows(*before, e->weightRows);
        e->WAfter = gatherRows(W, e->weightRows);
        char text[200];
        if (guard && guard->kept < 1.0)
          std::snprintf(text, sizeof text, "Stroke (%s) softened to 1/%.0f: at full strength it folded the picture. %ld samples re-optimized in %.0f ms.",
                        label.c_str(), 1.0 / guard->kept, long(st.timings.reoptimizeSamples), st.timings.reoptimizeMs);
        else
          std::snprintf(text, sizeof text, "Stroke (%s): %ld samples re-optimized in %.0f ms.", label.c_str(),
                        long(st.timings.reoptimizeSamples), st.timings.reoptimizeMs);
        postMessage(st, text, false);
        st.undo.push({label, std::move(*e)});
      },
      [e, before](app::Session& s) {
        scatterRows(s.W0, e->rows, e->W0Before);
        s.W = *before;
        s.params.kc.method = e->methodBefore;
      },
      guard);
}

bool startMethod(AppState& state, Method method, bool record) {
  if (!state.session || !state.meshSource || !canStart(state, "switch method")) return false;
  const Method before = state.bound->method;
  // W is a function of (W0, method) row by row (the optimizer reads only W0), so the undo entry
  // holds the two methods and undo re-optimizes, instead of storing W before and after; W itself
  // is kept only when it did not come from this optimizer.
  auto entry = std::make_shared<MethodEdit>(MethodEdit{before, method, {}});
  if (record && !state.weightsReproducible) entry->WBefore = state.session->W;
  std::function<void(AppState&)> done = [record, entry, method](AppState& st) {
    st.weightsReproducible = true;
    char text[160];
    const std::string name = app::upperCase(std::string(app::toString(method)));
    std::snprintf(text, sizeof text, "Method %s: the weights of all %ld samples re-optimized in %.0f ms.", name.c_str(),
                  long(st.session->samples.size()), st.timings.reoptimizeMs);
    postMessage(st, text, false);
    if (record) st.undo.push({std::string("method ") + std::string(app::toString(method)), std::move(*entry)});
  };
  return submitReoptimize(state, {}, method, "Re-optimizing", done, [before](app::Session& s) {
    try {
      app::reoptimize(s, before);  // W may be half overwritten: back to the method it came from
    } catch (const std::exception&) {
    }
  });
}

bool switchMethod(AppState& state, Method method) {
  if (!state.session || !canStart(state, "switch method")) return false;
  if (method == state.bound->method) return true;
  return startMethod(state, method, true);
}

bool startRestoreWeights(AppState& state, const std::vector<Index>& rows, const Weights& W0, const std::vector<Index>& weightRows,
                         const Weights& W,
                         Method method) {
  if (!state.session || !state.meshSource || !canStart(state, "undo")) return false;
  SessionPtr s = std::move(state.session);
  SourcePtr source = std::move(state.meshSource);
  auto mesh = std::make_shared<WarpMesh>(state.mesh);
  state.worker.submit("Restoring weights", [s, rows, W0, weightRows, W, method, source, mesh](JobContext&) -> Worker::Apply {
    try {
      scatterRows(s->W0, rows, W0);
      scatterRows(s->W, weightRows, W);
      s->params.kc.method = method;
      s->field->update(s->W);
      source->W = source->sampler.evaluate(*s->field);
      mesh->setWeights(source->W);
      return [s, mesh, source](AppState& st) { takeBack(st, s, mesh, source); };
    } catch (const std::exception& ex) {
      return failure(s, std::string("Restoring weights failed: ") + ex.what(), source);
    }
  });
  return true;
}

void pollWorker(AppState& state) {
  Worker::Apply apply = state.worker.takeResult();
  if (!apply) return;
  try {
    apply(state);
  } catch (const std::exception& e) {
    postMessage(state, std::string("Internal error: ") + e.what(), true);
  }
}

void refreshDiagnostics(AppState& state) {
  if (!state.session || !state.session->hasField()) return;
  try {
    state.diagnostics = app::diagnose(*state.session, 40000);
  } catch (const std::exception& e) {
    postMessage(state, std::string("Diagnostics failed: ") + e.what(), true);
  }
}

}  // namespace kc::ui
