#include "kc/ui/rigidity_edits.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "job_support.h"
#include "kc/app/rigidity.h"
#include "kc/core/spatial_grid.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"

namespace kc::ui {

using namespace detail;

namespace {

/// The rows where A and B (same shape) differ, and the columns where any of them differs.
void changedRowsAndColumns(const Weights& A, const Weights& B, std::vector<Index>& rows, std::vector<Index>& columns) {
  std::vector<char> col(static_cast<std::size_t>(A.cols()), 0);
  for (Index i = 0; i < A.rows(); ++i) {
    bool row = false;
    for (Index c = 0; c < A.cols(); ++c)
      if (A(i, c) != B(i, c)) row = true, col[static_cast<std::size_t>(c)] = 1;
    if (row) rows.push_back(i);
  }
  for (std::size_t c = 0; c < col.size(); ++c)
    if (col[c]) columns.push_back(static_cast<Index>(c));
}

/// Re-weights the display mesh in `columns` from the session's field (worker thread).
void reweightMesh(const app::Session& s, Document::MeshSource& source, WarpMesh& mesh, const std::vector<Index>& columns) {
  if (columns.empty()) return;  // (an empty list would mean every column)
  source.sampler.updateColumns(*s.field, columns, source.W);
  mesh.setWeights(source.W);
}

/// The ρ shown after a job: the bound snapshot's (takeBack's, or after a failure the one from
/// before the job, whose ρ the session is back to), and the tint follows.
void showSessionRigidity(AppState& st) {
  st.solvingRigidity.reset();
  st.rigidityVersion.bump();
}

/// What the main thread does after a cancelled rigidity job: the session back, the stroke taken back.
Worker::Apply strokeTakenBack(const SessionPtr& s, const SourcePtr& source) {
  return [s, source](AppState& st) {
    takeBack(st, s, nullptr, source);
    showSessionRigidity(st);
    postMessage(st, "Rigidity cancelled: the stroke was taken back.", false);
  };
}

}  // namespace

std::string rigiditySolveSummary(const app::RigidityUpdate& u) {
  char text[240];
  if (!u.report.solver.converged)
    std::snprintf(text, sizeof text, "Rigidity: the solver stopped before it was done; the region is as rigid as it got.");
  else
    std::snprintf(text, sizeof text, "Rigidity: %ld sample points held rigid (%.0f ms).", long(u.report.region), 1e3 * u.seconds);
  return text;
}

std::string rigiditySolveDetails(const app::RigidityUpdate& u) {
  const RigidityQpReport& q = u.report.solver;
  const bool admm = q.method == RigidityQpMethod::Splitting;  // a large region, or an active set that did not settle
  char text[240];
  std::snprintf(text, sizeof text, "rigidity: %ld samples, %ld controls; %s, %d %s%s", long(u.report.region), long(u.report.controls),
                admm ? "ADMM" : "active set", q.iterations, admm ? "iterations" : "rounds", q.converged ? "" : ", not converged");
  return text;
}

bool anyRigid(const std::vector<double>& rho) {
  return std::any_of(rho.begin(), rho.end(), [](double r) { return r > 0.0; });
}

const std::vector<double>& boundRigidity(const Document& doc) {
  static const std::vector<double> none;
  if (doc.solvingRigidity) return *doc.solvingRigidity;
  return doc.bound ? doc.bound->rigidity : none;
}

std::string rigidityProblem(const Document& doc) {
  const app::BackendCapabilities caps = shownCapabilities(doc);
  if (!caps.rigidity)
    return "rigid regions are kept by KC weights only (choose KC in the Bind panel and bind again)" +
           (caps.why.empty() ? std::string() : ": " + caps.why);
  if (!doc.bound) return "bind a cage first: the brush paints the samples of a bound picture";
  if (!caps.targets) return caps.why;
  return {};
}

std::vector<double> carryRigidity(const SampleSet& from, const std::vector<double>& rho, const SampleSet& to,
                                  const std::vector<double>& base, double h) {
  std::vector<double> out(static_cast<std::size_t>(to.size()), 0.0);
  for (std::size_t i = 0; i < out.size() && i < base.size(); ++i) out[i] = base[i];
  if (rho.size() != static_cast<std::size_t>(from.size()) || !anyRigid(rho) || !(h > 0.0)) return out;
  const SpatialGrid grid(from.X, 1.5 * h);
  for (Index s = 0; s < to.size(); ++s) {
    const SampleKind kind = to.kind[static_cast<std::size_t>(s)];
    if (kind != SampleKind::Interior && kind != SampleKind::Line) continue;
    double best = 1e300, value = 0.0;
    grid.forEachWithin(to.X.row(s).transpose(), 1.5 * h, [&](Index j, double d2) {
      if (d2 < best) best = d2, value = rho[static_cast<std::size_t>(j)];
    });
    out[static_cast<std::size_t>(s)] = std::max(out[static_cast<std::size_t>(s)], value);
  }
  return out;
}

bool startRigidity(AppState& state, std::vector<double> rho, std::string label, bool record) {
  const std::string problem = rigidityProblem(state);
  if (!problem.empty()) {
    postMessage(state, "Cannot change the rigidity: " + problem + ".", false);
    return false;
  }
  if (!state.session || !state.meshSource || !canStart(state, "change the rigidity")) return false;
  const auto t0 = std::chrono::steady_clock::now();
  SessionPtr s = std::move(state.session);
  SourcePtr source = std::move(state.meshSource);
  auto mesh = std::make_shared<WarpMesh>(state.mesh);  // the worker re-weights a copy
  std::vector<double> before = s->rigidity;
  before.resize(static_cast<std::size_t>(s->samples.size()), 0.0);
  state.solvingRigidity = rho;  // the tint shows the stroke while it is solved
  state.rigidityVersion.bump();
  state.worker.submit("Rigidity", [s, source, mesh, rho, before, label, record, t0](JobContext& ctx) -> Worker::Apply {
    const Weights W = s->W;
    const std::vector<double> stored = s->rigidity;
    try {
      if (!ctx.progress("rigidity: solving around the painted region", 0.05)) return strokeTakenBack(s, source);
      app::RigidityUpdate u;
      try {
        u = app::setRigidity(*s, rho, [&ctx](const char* stage, double f) { return ctx.progress(stage, 0.05 + 0.75 * f); });
      } catch (const Cancelled&) {  // setRigidity put the session back
        return strokeTakenBack(s, source);
      }
      auto edit = std::make_shared<RigidityEdit>();
      edit->before = before;
      edit->after = rho;
      changedRowsAndColumns(W, s->W, edit->rows, edit->columns);
      edit->WBefore = gatherRows(W, edit->rows);
      edit->WAfter = gatherRows(s->W, edit->rows);
      if (!ctx.progress("warp mesh", 0.8)) {  // cancelled during the solve: put everything back
        scatterRows(s->W, edit->rows, edit->WBefore);
        s->rigidity = stored;
        if (!edit->columns.empty()) s->field->update(s->W, edit->columns);
        return strokeTakenBack(s, source);
      }
      const auto t2 = std::chrono::steady_clock::now();
      reweightMesh(*s, *source, *mesh, edit->columns);
      const double meshMs = msSince(t2);
      return [s, source, mesh, edit, label, record, u, meshMs, t0](AppState& st) {
        takeBack(st, s, edit->columns.empty() ? nullptr : mesh, source);
        showSessionRigidity(st);
        if (record) st.undo.push({label, std::move(*edit)});
        st.unsaved = true;
        st.timings.reoptimizeMs = 1e3 * u.seconds;
        st.timings.reoptimizeSamples = static_cast<Index>(u.rows.size());
        st.timings.meshWeightsMs = meshMs;
        noteReleaseResult(st, t0);
        if (u.report.nodes > 0) {
          postMessage(st, rigiditySolveSummary(u), !u.report.solver.converged);
          st.rigidityDetails = rigiditySolveDetails(u);
        }
      };
    } catch (const std::exception& ex) {
      s->W = W;
      s->rigidity = stored;
      rebuildFromW(*s, *source);
      const std::string text = std::string("Rigidity failed: ") + ex.what();
      return [s, source, text](AppState& st) {
        st.session = s;
        st.meshSource = source;
        showSessionRigidity(st);
        postMessage(st, text, true);
      };
    }
  });
  return true;
}

bool startRestoreRigidity(AppState& state, const RigidityEdit& edit, bool forward) {
  if (!state.session || !state.meshSource || !canStart(state, "undo")) return false;
  if (edit.before.size() != static_cast<std::size_t>(state.session->samples.size()) || edit.before.size() != edit.after.size())
    return false;
  SessionPtr s = std::move(state.session);
  SourcePtr source = std::move(state.meshSource);
  auto mesh = std::make_shared<WarpMesh>(state.mesh);
  const std::vector<double> rho = forward ? edit.after : edit.before;
  const Weights R = forward ? edit.WAfter : edit.WBefore;
  state.solvingRigidity = rho;
  state.rigidityVersion.bump();
  state.worker.submit("Restoring rigidity", [s, source, mesh, rho, R, rows = edit.rows, columns = edit.columns](JobContext&) -> Worker::Apply {
    try {
      scatterRows(s->W, rows, R);
      s->rigidity = rho;
      if (!columns.empty()) s->field->update(s->W, columns);
      reweightMesh(*s, *source, *mesh, columns);
      return [s, source, mesh, columns](AppState& st) {
        takeBack(st, s, columns.empty() ? nullptr : mesh, source);
        showSessionRigidity(st);
      };
    } catch (const std::exception& ex) {
      rebuildFromW(*s, *source);
      return [s, source, text = std::string("Restoring the rigidity failed: ") + ex.what()](AppState& st) {
        st.session = s;
        st.meshSource = source;
        showSessionRigidity(st);
        postMessage(st, text, true);
      };
    }
  });
  return true;
}

bool clearRigidity(AppState& state) {
  const std::vector<double>& rho = boundRigidity(state);
  if (!anyRigid(rho)) return false;
  return startRigidity(state, std::vector<double>(rho.size(), 0.0), "clear rigidity");
}

}  // namespace kc::ui
