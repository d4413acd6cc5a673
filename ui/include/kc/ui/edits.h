#pragma once
/// Setters of the document that mark what is stale (STYLE.md: "one method that sets the value and
/// marks what is stale"), and undo/redo. Main thread only.

#include <cstddef>
#include <string>

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Longest message shown, bytes: a longer one keeps its head and tail (app::oneLine), so no
/// message, whatever a file or a lower layer put in it, draws more than a few thousand vertices.
inline constexpr std::size_t kMaxMessageBytes = 1000;
/// Shows a line in the message bar (errors stay until dismissed): one line (control characters
/// escaped) of at most kMaxMessageBytes.
void postMessage(Interaction& interaction, std::string text, bool error);

/// Sets the pose (one handle per bound control); the deformation is redone next frame.
void setPose(Document& doc, Pose pose);
/// Records the change from `before` to the current pose as one undo entry and marks unsaved.
void commitPose(Document& doc, const Pose& before, std::string label);
/// Back to the rest pose (undoable).
void resetPose(AppState& state);

/// A cage the user has finished: a closed polygon, or an edge graph from a cage file (closed loops
/// and open sticks, e.g. a stick figure). Anything else is a polyline still being drawn.
inline bool cageComplete(const Cage& cage) { return cage.closed || !cage.edges.empty(); }
/// An edge graph (sticks): its points can be moved but not added or removed in the GUI, whose
/// cage tool draws polygons; the edges come from the cage file.
inline bool cageIsEdgeGraph(const Cage& cage) { return !cage.closed && !cage.edges.empty(); }

/// Sets the draft cage and re-validates it (cageValid, cageStatus).
void setDraftCage(Document& doc, Cage cage);
/// Records the change from `before` to the current draft cage as one undo entry.
void commitCage(Document& doc, const Cage& before, std::string label);

/// Undo / redo the newest entry. Weight edits need the session (not while a job runs); they
/// restore W0 and W bit for bit and refresh the field and the display mesh on the worker.
/// Returns false (with a message) when nothing could be done.
bool undo(AppState& state);
bool redo(AppState& state);

/// Re-deforms the display mesh when the pose or the mesh changed since the last call
/// (WarpMesh::deform, one sparse product). Returns true when it deformed.
bool updateDeformation(AppState& state);

/// Switches tool, ending any drag in progress. The brush is refused (with the reason) when
/// shownCapabilities(state) has no painting, the rigidity brush when rigidityProblem() names one.
void selectTool(AppState& state, Tool tool);

/// What the panels offer: the bound session's capabilities, or before a bind those of the backend
/// chosen in the Bind panel (doc.bindParams.backend). Panels grey out what is missing and show
/// `why` as the tooltip; they never ask for the backend's name.
app::BackendCapabilities shownCapabilities(const Document& doc);

}  // namespace kc::ui
