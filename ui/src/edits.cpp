#include "kc/ui/edits.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "kc/app/errors.h"
#include "kc/ui/jobs.h"
#include "kc/ui/line_edits.h"
#include "kc/ui/rigidity_edits.h"

namespace kc::ui {

double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void postMessage(Interaction& interaction, std::string text, bool error) {
  if (interaction.messages.size() >= 8) interaction.messages.erase(interaction.messages.begin());
  interaction.messages.push_back({app::oneLine(text, kMaxMessageBytes), error});
}

void setPose(Document& doc, Pose pose) {
  doc.pose = std::move(pose);
  doc.poseVersion.bump();
}

void commitPose(Document& doc, const Pose& before, std::string label) {
  if (before.size() == doc.pose.size()) {
    bool same = true;
    for (std::size_t i = 0; i < before.size() && same; ++i)
      same = before[i].translate == doc.pose[i].translate && before[i].rotate == doc.pose[i].rotate;
    if (same) return;
  }
  doc.undo.push({std::move(label), PoseEdit{before, doc.pose}});
  doc.unsaved = true;
}

void resetPose(AppState& state) {
  if (!state.bound) return;
  const Pose before = state.pose;
  setPose(state, restPose(state.bound->cage.size()));
  commitPose(state, before, "reset pose");
}

void setDraftCage(Document& doc, Cage cage) {
  doc.cage = std::move(cage);
  if (!cageComplete(doc.cage)) {
    doc.cageValid = false;
    doc.cageStatus = doc.cage.size() < 3 ? "Click on the picture to add cage points (at least 3)."
                                         : "The cage is open: click its first point to close it.";
    return;
  }
  try {
    validateCage(doc.cage);
    doc.cageValid = true;
    doc.cageStatus.clear();
  } catch (const std::invalid_argument& e) {
    doc.cageValid = false;
    doc.cageStatus = e.what();
  }
}

void commitCage(Document& doc, const Cage& before, std::string label) {
  doc.undo.push({std::move(label), CageEdit{before, doc.cage}});
  doc.unsaved = true;
}

namespace {

/// Applies one side of an entry (forward = redo).
bool applyEntry(AppState& state, const UndoEntry& entry, bool forward) {
  return std::visit(
      [&](const auto& edit) -> bool {
        using T = std::decay_t<decltype(edit)>;
        if constexpr (std::is_same_v<T, PoseEdit>) {
          const Pose& p = forward ? edit.after : edit.before;
          if (!p.empty() && (!state.bound || p.size() != static_cast<std::size_t>(state.bound->cage.size()))) return false;
          setPose(state, p);
        } else if constexpr (std::is_same_v<T, CageEdit>) {
          setDraftCage(state, forward ? edit.after : edit.before);
        } else if constexpr (std::is_same_v<T, RigidityEdit>) {
          if (!state.session) return false;
          return startRestoreRigidity(state, edit, forward);
        } else if constexpr (std::is_same_v<T, BindEdit>) {
          return swapBoundDocument(state, edit);
        } else if constexpr (std::is_same_v<T, LinesEdit>) {
          return applyLines(state, forward ? edit.after : edit.before);
        } else if constexpr (std::is_same_v<T, MethodEdit>) {
          if (!state.session) return false;
          if (forward || edit.WBefore.rows() == 0) return startMethod(state, forward ? edit.after : edit.before, false);
          // Weights from a session file: put them back as they were.
          state.weightsReproducible = false;
          return startRestoreWeights(state, {}, state.session->W0, {}, edit.WBefore, edit.before);
        } else {
          if (!state.session) return false;
          return startRestoreWeights(state, edit.rows, forward ? edit.W0After : edit.W0Before, edit.weightRows,
                                     forward ? edit.WAfter : edit.WBefore, forward ? edit.methodAfter : edit.methodBefore);
        }
        return true;
      },
      entry.edit);
}

/// Weight edits, method switches and rigidity strokes run on the worker with the session; a bind's
/// undo swaps the session.
bool needsSession(const Edit& e) {
  return std::holds_alternative<WeightEdit>(e) || std::holds_alternative<MethodEdit>(e) || std::holds_alternative<RigidityEdit>(e) ||
         std::holds_alternative<BindEdit>(e);
}

bool endInteractions(AppState& state) {
  state.poseTool.cancel(state);
  state.brushTool.cancel(state);
  state.cageTool.cancel(state);
  state.lineTool.cancel(state);
  state.rigidTool.cancel(state);
  return true;
}

}  // namespace

bool undo(AppState& state) {
  if (!state.undo.canUndo()) return false;
  endInteractions(state);
  if (needsSession(state.undo.nextUndo()->edit) && !state.session) {
    postMessage(state, "Busy: undo after the current job has finished.", false);
    return false;
  }
  UndoEntry& e = state.undo.popUndo();
  if (!applyEntry(state, e, false)) {
    const std::string label = e.label;
    state.undo.popRedo();
    postMessage(state, "Cannot undo '" + label + "' now.", false);
    return false;
  }
  if (!std::holds_alternative<BindEdit>(e.edit)) postMessage(state, "Undone: " + e.label + ".", false);  // a bind says which is back
  state.unsaved = true;
  return true;
}

bool redo(AppState& state) {
  if (!state.undo.canRedo()) return false;
  endInteractions(state);
  if (needsSession(state.undo.nextRedo()->edit) && !state.session) {
    postMessage(state, "Busy: redo after the current job has finished.", false);
    return false;
  }
  UndoEntry& e = state.undo.popRedo();
  if (!applyEntry(state, e, true)) {
    const std::string label = e.label;
    state.undo.popUndo();
    postMessage(state, "Cannot redo '" + label + "' now.", false);
    return false;
  }
  if (!std::holds_alternative<BindEdit>(e.edit)) postMessage(state, "Redone: " + e.label + ".", false);
  state.unsaved = true;
  return true;
}

namespace {

/// After a full deform: the status bar says when the picture folds more than it did (and how to
/// undo what folded it) or no longer folds.
void tellFolds(AppState& state) {
  const Index folds = state.deformReport.flippedTriangles;
  const Index before = std::exchange(state.foldsTold, folds);
  if (folds == 0 && before > 0) postMessage(state, "The picture no longer folds over itself.", false);
  if (folds <= before) return;
  std::string fix = "Undo (Ctrl+Z) the last change to go back";
  if (const UndoEntry* last = state.undo.nextUndo()) {
    if (std::holds_alternative<WeightEdit>(last->edit)) fix = "Undo the stroke (Ctrl+Z), or paint with a lower Strength";
    else if (std::holds_alternative<MethodEdit>(last->edit)) fix = "Undo the method switch (Ctrl+Z) to go back";
    else if (std::holds_alternative<PoseEdit>(last->edit)) fix = "Undo the move (Ctrl+Z), or move the points less far";
  } else {
    fix = "Move the points less far";
  }
  char count[64];
  std::snprintf(count, sizeof count, "%ld small triangle%s", long(folds), folds == 1 ? "" : "s");
  postMessage(state, std::string("The picture folds over itself (") + count + " turned over, marked red). " + fix + ".", false);
  state.messages.back().offersUndo = state.undo.canUndo();
}

}  // namespace

bool updateDeformation(AppState& state) {
  if (!state.mesh.hasWeights()) return false;
  // While a control is dragged the background's fold repair starts from the previous picture
  // (cheap, follows the drag); after the release the pose gets the full repair, as in the export.
  const bool live = state.tool == Tool::Pose && state.poseTool.active() && !state.poseTool.selectingRect();
  // A full deform of this pose and mesh also serves a live one.
  if (state.deformed.current({state.poseVersion, state.meshVersion, false}) ||
      (live && state.deformed.current({state.poseVersion, state.meshVersion, true})))
    return false;
  if (state.pose.size() != static_cast<std::size_t>(state.mesh.cage().size())) return false;
  try {
    state.deformReport = state.mesh.deform(state.pose, live ? DeformPass::Live : DeformPass::Final);
  } catch (const std::exception& e) {
    postMessage(state, std::string("Deformation failed: ") + e.what(), true);
  }
  if (!live) tellFolds(state);
  state.timings.deformMs = state.deformReport.seconds * 1e3;
  state.deformed.set({state.poseVersion, state.meshVersion, live});
  return true;
}

app::BackendCapabilities shownCapabilities(const Document& doc) {
  if (doc.bound) return doc.bound->capabilities;
  try {
    return app::backendFor(doc.bindParams.backend).capabilities();
  } catch (const std::invalid_argument&) {
    return {};  // an unknown name: the bind itself reports it
  }
}

void selectTool(AppState& state, Tool tool) {
  if (state.tool == tool) return;
  if (tool == Tool::Brush && !shownCapabilities(state).painting) {
    postMessage(state, "The brush is not available: " + shownCapabilities(state).why, false);
    return;
  }
  if (tool == Tool::Rigid) {
    const std::string problem = rigidityProblem(state);
    if (!problem.empty()) {
      postMessage(state, "The rigidity brush is not available: " + problem + ".", false);
      return;
    }
  }
  if (tool == Tool::Lines && !shownCapabilities(state).lines) {
    postMessage(state, "The line tool needs KC weights: lines are kept straight by the kernel backend (choose KC in the Bind panel).", false);
    return;
  }
  endInteractions(state);
  state.tool = tool;
}

}  // namespace kc::ui
