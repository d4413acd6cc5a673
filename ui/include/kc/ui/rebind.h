#pragma once
/// Binding again without losing the person's work: the question before a bind that leaves paint
/// strokes behind, the pose carried to the new cage, and the bind as one undo step (BindEdit) that
/// swaps the previous session, its display mesh and pose back. Main thread.

#include <memory>
#include <string>
#include <vector>

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Bind as the user asks for it (Bind button, Ctrl+B, a loaded cage): when the present weights
/// hold paint strokes a new bind cannot carry over (strokesLostByRebind), or the chosen backend
/// cannot keep the document's lines or rigid regions (structureLeftOut), a question names them
/// first (AppState::unsavedPrompt with a question: "Bind again" or Cancel); else startBind.
/// Before the first bind, lines or rigid regions the backend cannot keep refuse the bind (an
/// error message says so). Returns true when the bind started.
bool requestBind(AppState& state);

/// The sentence for the question before a bind whose backend cannot keep the document's lines
/// or rigid regions (app::unsupportedStructure; startBind binds without them, and the present
/// bind keeps them); before the first bind, the refusal requestBind shows instead (nothing would
/// keep them); empty when there are none or the backend keeps them.
std::string structureLeftOut(const Document& doc);

/// Labels of the paint strokes in the present weights ("paint w3"), oldest first: the weight
/// edits on the undo stack since the newest bind. A new bind computes the weights anew from the
/// cage, so these do not carry over (they stay one undo away, behind the bind).
std::vector<std::string> strokesLostByRebind(const Document& doc);

/// The pose of `after`'s control points that keeps `pose` (of `before`'s points): handle by handle
/// when the two cages have as many points, else for each point of `after` the handle of the point
/// of `before` at the same rest position (the rest pose for new points).
Pose carriedPose(const Cage& before, const Pose& pose, const Cage& after);

/// A bound document as a bind left it (BindEdit): the session, its display mesh and the source of
/// the mesh's weights, the pose and whether W came from this optimizer.
struct BoundDocument {
  std::shared_ptr<app::Session> session;
  std::shared_ptr<WarpMesh> mesh;
  std::shared_ptr<Document::MeshSource> source;
  Pose pose;
  bool weightsReproducible = false;
};

/// The newest bind step on the undo stack when only pose edits came after it (at least one): the
/// bind "Previous bind" goes back to once points were dragged; null otherwise.
const BindEdit* bindBehindPoses(const UndoStack& undo);

/// "Previous bind" after pose edits: the document before the newest bind (bindBehindPoses), its
/// weights and display mesh, installed in the present pose carried to its cage, as a new bind step
/// (Ctrl+Z or Previous bind again comes back to the present one, in the pose it had). False when
/// there is none or a job holds the session.
bool showPreviousBind(AppState& state);

/// Undo or redo of a bind: swaps the present bound document with edit.other (kept in the edit for
/// the way back). False when the session is held by a job.
bool swapBoundDocument(AppState& state, const BindEdit& edit);

}  // namespace kc::ui
