#include "kc/ui/jobs.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "kc/app/diagnostics.h"
#include "kc/app/export.h"
#include "kc/app/pipeline.h"
#include "kc/ui/edits.h"

namespace kc::ui {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

using SessionPtr = std::shared_ptr<app::Session>;
using MeshPtr = std::shared_ptr<WarpMesh>;
using SourcePtr = std::shared_ptr<AppState::MeshSource>;

/// Installs a new display mesh (after a weight change) and hands the session back.
void takeBack(AppState& state, SessionPtr session, const MeshPtr& mesh, SourcePtr source) {
  state.session = std::move(session);
  state.method = state.session->params.method;
  if (mesh) {
    state.mesh = std::move(*mesh);
    ++state.meshRevision;
  }
  if (source) state.meshSource = std::move(source);
  state.diagnostics.reset();
}

/// A closure that hands the session back and reports `text` as an error.
Worker::Apply failure(SessionPtr session, std::string text) {
  return [session, text](AppState& st) {
    if (session) st.session = session;
    postMessage(st, text, true);
  };
}

bool canStart(AppState& state, const char* what) {
  if (state.worker.busy()) {
    postMessage(state, std::string("Busy: ") + what + " after the current job has finished.", false);
    return false;
  }
  return true;
}

}  // namespace

WarpMeshOptions displayMeshOptions(int width, int height) {
  WarpMeshOptions o;
  const double area = double(width) * double(height);
  if (area / (o.spacing * o.spacing) > 70000.0) o.spacing = std::sqrt(area / 70000.0);
  return o;
}

DisplayMesh buildDisplayMesh(const app::Session& session, const WarpMeshOptions& options) {
  DisplayMesh d;
  d.source = std::make_shared<AppState::MeshSource>();
  d.mesh = std::make_shared<WarpMesh>(app::buildWarpMesh(session, options, nullptr, &d.source->sampler, &d.source->W));
  return d;
}

void installSession(AppState& state, std::shared_ptr<app::Session> session, DisplayMesh display) {
  const app::Session& s = *session;
  state.session = std::move(session);
  state.bound = true;
  state.boundCage = s.cage;
  state.samples = s.samples;
  state.method = s.params.method;
  state.bindParams = s.params;
  setDraftCage(state, s.cage);
  setPose(state, s.pose.size() == static_cast<std::size_t>(s.cage.size()) ? s.pose : restPose(s.cage.size()));
  state.mesh = std::move(*display.mesh);
  state.meshSource = std::move(display.source);
  ++state.meshRevision;
  state.selection.clear();
  if (state.activeControl >= s.cage.size() || state.activeControl < 0) state.activeControl = 0;
  state.undo.clear();
  state.diagnostics.reset();
  state.timings.bindSeconds = s.timings.total;
}

bool startBind(AppState& state) {
  if (!canStart(state, "bind")) return false;
  if (state.source.empty()) {
    postMessage(state, "Open an image before binding.", true);
    return false;
  }
  if (!state.cageValid) {
    postMessage(state, "The cage cannot be bound: " + state.cageStatus, true);
    return false;
  }
  SessionPtr previous = std::move(state.session);
  const Cage cage = state.cage;
  const int w = state.source.width, h = state.source.height;
  const app::BindParams params = state.bindParams;
  const std::string image = state.imagePath;
  const WarpMeshOptions meshOptions = displayMeshOptions(w, h);
  state.worker.submit("Binding", [=](JobContext& ctx) -> Worker::Apply {
    try {
      app::BindReport report;
      auto s = std::make_shared<app::Session>(
          app::bind(cage, w, h, params, &report, [&](const char* stage, double f) { return ctx.progress(stage, 0.9 * f); }));
      s->image = image;
      if (!ctx.progress("warp mesh", 0.92)) throw app::BindCancelled();
      DisplayMesh display = buildDisplayMesh(*s, meshOptions);
      return [s, display](AppState& st) {
        installSession(st, s, display);
        st.unsaved = true;
        st.tool = Tool::Pose;
        char text[160];
        std::snprintf(text, sizeof text, "Bound %ld control points, %ld samples in %.2f s.", long(s->cage.size()),
                      long(s->samples.size()), s->timings.total);
        postMessage(st, text, false);
      };
    } catch (const app::BindCancelled&) {
      return [previous](AppState& st) {
        st.session = previous;
        postMessage(st, "Bind cancelled.", false);
      };
    } catch (const std::exception& e) {
      return failure(previous, std::string("Bind failed: ") + e.what());
    }
  });
  return true;
}

bool startReoptimize(AppState& state, WeightEdit edit, std::string label) {
  if (!state.session || !canStart(state, "re-optimize")) return false;
  SessionPtr s = std::move(state.session);
  SourcePtr source = state.meshSource;
  auto mesh = std::make_shared<WarpMesh>(state.mesh);  // the worker re-weights a copy
  auto e = std::make_shared<WeightEdit>(std::move(edit));
  const auto t0 = std::chrono::steady_clock::now();
  state.worker.submit("Re-optimizing", [s, e, label, source, mesh, t0](JobContext& ctx) -> Worker::Apply {
    try {
      ctx.progress("optimization", 0.1);
      const auto t1 = std::chrono::steady_clock::now();
      std::vector<Index> columns;
      const OptimizeReport r = app::reoptimize(*s, e->methodAfter, e->rows, &columns);
      const double reoptimizeMs = msSince(t1);
      ctx.progress("warp mesh", 0.6);
      const auto t2 = std::chrono::steady_clock::now();
      // Only the controls whose weights changed are re-evaluated at the mesh vertices.
      source->sampler.updateColumns(s->field.coefficients, columns, source->W);
      mesh->setWeights(source->W);
      const double meshMs = msSince(t2);
      e->WAfter = gatherRows(s->W, e->rows);
      return [s, e, label, mesh, source, reoptimizeMs, meshMs, t0, solved = r.solved](AppState& st) {
        takeBack(st, s, mesh, source);
        st.undo.push({label, std::move(*e)});
        st.unsaved = true;
        st.timings.reoptimizeMs = reoptimizeMs;
        st.timings.reoptimizeSamples = solved;
        st.timings.meshWeightsMs = meshMs;
        st.timings.releaseToPictureMs = msSince(t0);  // + this frame's deform and upload
      };
    } catch (const std::exception& ex) {
      scatterRows(s->W0, e->rows, e->W0Before);
      if (e->WBefore.rows() > 0) scatterRows(s->W, e->rows, e->WBefore);
      s->params.method = e->methodBefore;
      // The field and the vertex weights may be half updated: rebuild both from W.
      try {
        s->field.coefficients = s->field.interpolator.solve(s->W);
        source->W = source->sampler.evaluate(s->field.coefficients);
      } catch (const std::exception&) {
      }
      return failure(s, std::string("Re-optimization failed: ") + ex.what());
    }
  });
  return true;
}

bool switchMethod(AppState& state, Method method) {
  if (!state.session || !canStart(state, "switch method")) return false;
  if (method == state.method) return true;
  WeightEdit edit;
  edit.W0Before = edit.W0After = state.session->W0;
  edit.WBefore = state.session->W;
  edit.methodBefore = state.method;
  edit.methodAfter = method;
  return startReoptimize(state, std::move(edit), std::string("method ") + std::string(app::toString(method)));
}

bool startRestoreWeights(AppState& state, const std::vector<Index>& rows, const Weights& W0, const Weights& W,
                         Method method) {
  if (!state.session || !canStart(state, "undo")) return false;
  SessionPtr s = std::move(state.session);
  SourcePtr source = state.meshSource;
  auto mesh = std::make_shared<WarpMesh>(state.mesh);
  state.worker.submit("Restoring weights", [s, rows, W0, W, method, source, mesh](JobContext&) -> Worker::Apply {
    try {
      scatterRows(s->W0, rows, W0);
      scatterRows(s->W, rows, W);
      s->params.method = method;
      s->field.coefficients = s->field.interpolator.solve(s->W);
      source->W = source->sampler.evaluate(s->field.coefficients);
      mesh->setWeights(source->W);
      return [s, mesh, source](AppState& st) { takeBack(st, s, mesh, source); };
    } catch (const std::exception& ex) {
      return failure(s, std::string("Restoring weights failed: ") + ex.what());
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
  if (!state.session || !state.session->field.ready()) return;
  try {
    state.diagnostics = app::diagnose(*state.session, 40000);
  } catch (const std::exception& e) {
    postMessage(state, std::string("Diagnostics failed: ") + e.what(), true);
  }
}

}  // namespace kc::ui
