// Binding again without losing the person's work (rebind.h): the question about strokes that
// cannot carry over, the pose carried to the new cage, and the bind as one undo step (BindEdit).
#include "kc/ui/rebind.h"

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "kc/app/backend.h"
#include "kc/app/text.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/rigidity_edits.h"
#include "job_support.h"

namespace kc::ui {
namespace {

/// Binds kept on the undo stack (BindEdit): each holds a session with its weights and display mesh.
constexpr std::size_t kKeptBinds = 4;

/// Pushes a bind step holding `other`; each BindEdit holds a whole session and mesh, so past
/// kKeptBinds the oldest go, with the edits before them.
void pushBind(UndoStack& history, const char* label, std::shared_ptr<BoundDocument> other) {
  history.push({label, BindEdit{std::move(other)}});
  std::size_t binds = 0;
  const std::vector<UndoEntry>& entries = history.undoEntries();
  for (std::size_t k = entries.size(); k-- > 0;)
    if (std::holds_alternative<BindEdit>(entries[k].edit) && ++binds > kKeptBinds) {
      history.dropOldest(k + 1);
      break;
    }
}

/// The present bound document with `session` (the display mesh moved out of `st`): what a bind
/// step keeps of the side it leaves.
std::shared_ptr<BoundDocument> takePresent(AppState& st, SessionPtr session) {
  return std::make_shared<BoundDocument>(BoundDocument{std::move(session), std::make_shared<WarpMesh>(std::move(st.mesh)),
                                                       st.meshSource, st.pose, st.weightsReproducible});
}

/// Makes a bound session the present document in `pose`, keeping the undo history (installSession
/// clears it) and the tool `tool` where the session's backend can do it (else Pose).
void installKeepingHistory(AppState& st, SessionPtr session, DisplayMesh display, bool reproducible, const Pose& pose,
                           Tool tool) {
  UndoStack history = std::move(st.undo);
  installSession(st, std::move(session), std::move(display), reproducible);
  st.undo = std::move(history);
  setPose(st, pose);
  selectTool(st, tool);
}

}  // namespace

namespace detail {

void carryRigidityTo(AppState& st, const SampleSet& oldSamples, const std::vector<double>& oldRigidity, double oldSpacing,
                     const app::Session& s) {
  // A backend without rigidity (LBC) starts without it; requestBind said so before the bind.
  if (!anyRigid(oldRigidity) || !app::backendFor(s.params.backend).capabilities().rigidity) return;
  std::vector<double> rho = carryRigidity(oldSamples, oldRigidity, s.samples, s.rigidity, std::max(oldSpacing, s.params.spacing));
  if (rho != s.rigidity) startRigidity(st, std::move(rho), "rigidity after the bind", /*record=*/false);
}

void installReplacing(AppState& st, SessionPtr previous, std::shared_ptr<app::Session> s, DisplayMesh display) {
  auto before = takePresent(st, std::move(previous));
  const std::shared_ptr<const BoundSnapshot> bound = st.bound ? st.bound : std::make_shared<const BoundSnapshot>();
  const std::vector<double> oldRigidity = boundRigidity(st);
  const Pose pose = carriedPose(bound->cage, before->pose, s->cage);
  installKeepingHistory(st, s, std::move(display), true, pose, st.tool == Tool::Cage ? Tool::Pose : st.tool);
  pushBind(st.undo, "bind again", std::move(before));
  carryRigidityTo(st, bound->samples, oldRigidity, bound->spacing, *s);
}

std::string rebindQuestion(const Document& doc) {
  if (!doc.bound) return "";
  const std::vector<std::string> strokes = strokesLostByRebind(doc);
  if (strokes.empty()) return "";
  std::string names;
  for (std::size_t k = 0; k < strokes.size(); ++k) names += (k == 0 ? "" : k + 1 == strokes.size() ? " and " : ", ") + strokes[k];
  const std::string count = strokes.size() == 1 ? "Your paint stroke (" : "Your " + std::to_string(strokes.size()) + " paint strokes (";
  return count + names + ") cannot be carried over: binding again computes the weights anew from the cage. The pose is kept, " +
         "and the present weights, " + (strokes.size() == 1 ? "stroke" : "strokes") + " included, stay one undo (Ctrl+Z) away.";
}

}  // namespace detail

using namespace detail;

std::vector<std::string> strokesLostByRebind(const Document& doc) {
  std::vector<std::string> strokes;
  for (const UndoEntry& e : doc.undo.undoEntries()) {
    if (std::holds_alternative<BindEdit>(e.edit)) strokes.clear();  // those before it belong to the previous bind
    else if (std::holds_alternative<WeightEdit>(e.edit)) strokes.push_back(e.label);
  }
  return strokes;
}

std::string structureLeftOut(const Document& doc) {
  const app::Backend& backend = app::backendFor(doc.bindParams.backend);
  // Rigid parts painted with the rigidity brush count as rigid regions: they do not carry over either.
  const bool painted = doc.bound && anyRigid(boundRigidity(doc));
  const std::string missing = app::unsupportedStructure(doc.lines, backend.capabilities(), painted);
  if (missing.empty()) return "";
  const std::string name = app::upperCase(std::string(backend.name()));
  if (!doc.bound)  // no bind to keep them: the person decides
    return name + " cannot keep " + missing + ": choose KC to bind with them; to bind LBC, delete them first (with KC chosen)";
  return name + " cannot keep " + missing + ": it binds without your " + missing + ". They stay with the present bind, " +
         "one click away afterwards (Previous bind).";
}

bool requestBind(AppState& state) {
  if (!state.bound) {
    if (const std::string refusal = structureLeftOut(state); !refusal.empty()) {
      postMessage(state, refusal + ".", true);
      return false;
    }
  }
  std::string question = structureLeftOut(state);
  if (const std::string strokes = rebindQuestion(state); !strokes.empty()) question += (question.empty() ? "" : " ") + strokes;
  if (!question.empty()) {
    state.unsavedPrompt = PendingAction{"Bind again", [](AppState& st) { startBind(st); }, question};
    return false;
  }
  return startBind(state);
}

Pose carriedPose(const Cage& before, const Pose& pose, const Cage& after) {
  if (pose.size() != static_cast<std::size_t>(before.size())) return restPose(after.size());
  if (before.size() == after.size()) return pose;
  Pose out = restPose(after.size());
  for (Index i = 0; i < after.size(); ++i)
    for (Index j = 0; j < before.size(); ++j)
      if ((before.C.row(j) - after.C.row(i)).norm() < 1e-9) {
        out[static_cast<std::size_t>(i)] = pose[static_cast<std::size_t>(j)];
        break;
      }
  return out;
}

const BindEdit* bindBehindPoses(const UndoStack& undo) {
  const std::vector<UndoEntry>& entries = undo.undoEntries();
  for (std::size_t k = entries.size(); k-- > 0;) {
    if (std::holds_alternative<PoseEdit>(entries[k].edit)) continue;
    const auto* bind = std::get_if<BindEdit>(&entries[k].edit);
    return bind && k + 1 < entries.size() ? bind : nullptr;
  }
  return nullptr;
}

bool showPreviousBind(AppState& state) {
  const BindEdit* behind = bindBehindPoses(state.undo);
  if (!behind || !behind->other || !behind->other->session || !behind->other->mesh || !state.session || !state.bound ||
      state.worker.busy())
    return false;
  const BoundDocument& previous = *behind->other;
  auto present = takePresent(state, state.session);
  const Pose pose = carriedPose(state.bound->cage, present->pose, previous.session->cage);
  // The previous document stays in the bind step below, its session shared with it: the undo
  // stack is last in, first out, so every edit made to it from now on is undone before that step
  // swaps it back. Its display mesh and the mesh's source are copied (installing takes them).
  DisplayMesh display{std::make_shared<WarpMesh>(*previous.mesh),
                      previous.source ? std::make_shared<Document::MeshSource>(*previous.source) : nullptr};
  installKeepingHistory(state, previous.session, std::move(display), previous.weightsReproducible, pose, state.tool);
  pushBind(state.undo, "previous bind", std::move(present));
  postMessage(state,
              "Back to the " + std::string(app::backendFor(state.session->params.backend).displayName()) +
                  " bind, in the present pose (Previous bind again comes back).",
              false);
  return true;
}

bool swapBoundDocument(AppState& state, const BindEdit& edit) {
  if (!state.session || !edit.other || !edit.other->session || state.worker.busy()) return false;
  BoundDocument next = std::move(*edit.other);
  *edit.other = std::move(*takePresent(state, std::move(state.session)));
  installKeepingHistory(state, next.session, {next.mesh, next.source}, next.weightsReproducible, next.pose, state.tool);
  const app::Session& b = *state.session;
  const Index vertices = b.report.meshVertices();
  postMessage(
      state,
      "Back to the " + std::string(app::backendFor(b.params.backend).displayName()) + " bind (" +
          (vertices > 0 ? std::to_string(vertices) + " mesh vertices)." : std::to_string(b.samples.size()) + " samples)."),
      false);
  return true;
}

}  // namespace kc::ui
