#pragma once
/// Edits of the structure lines (thesis 5.3: lines kept straight, groups kept parallel) from the
/// line tool and its panel. Every edit is checked by the same code the CLI's --structure uses
/// (kc::validateLines, at the spacing of the next bind), recorded for undo (LinesEdit), and
/// re-binds a bound session (the lines' samples are part of the sampling). Main thread only.

#include <string>

#include "kc/app/session.h"
#include "kc/ui/app_state.h"

namespace kc::ui {

/// Index of the line of `lines` nearest to p (image pixels) within `radius`, or −1.
int pickLine(const app::Structure& lines, const Vec2& p, double radius);

/// Why `lines` cannot be bound over the draft cage (empty when they can): the backend has no
/// lines, the cage is not a valid closed cage, or kc::validateLines refuses them at the spacing of
/// the next bind (bindParamsFor; a graded bind with its rules: lines may cross, meet and run close
/// to or end on the cage). Lines are named "line k", as the Lines panel lists them.
std::string linesProblem(const AppState& state, const app::Structure& lines);

/// Makes `lines` the document's lines: refused with the reason as an error message when
/// linesProblem() says so or a job is running; otherwise recorded as one undo entry `label`,
/// marked unsaved, and a bound session is re-bound with them (progress and Cancel; the pose and
/// the undo history are kept). Returns true when accepted.
bool editLines(AppState& state, app::Structure lines, std::string label);
/// Sets the lines without checking or recording them (undo/redo of a LinesEdit) and re-binds a
/// bound session. False when a job is running.
bool applyLines(AppState& state, const app::Structure& lines);

/// The selected lines form the parallel group `name` (joining it if it exists). Needs at least
/// two lines in the group. Returns editLines' answer.
bool groupSelectedLines(AppState& state, const std::string& name);
/// The selected lines leave their parallel groups (a group left with one line dissolves).
bool ungroupSelectedLines(AppState& state);
/// Deletes the selected lines (a group left with one line dissolves).
bool deleteSelectedLines(AppState& state);

/// Dissolves parallel groups with fewer than two lines and forgets names no line uses
/// (renumbering StructureLine::group). Returns how many lines were ungrouped.
int tidyGroups(app::Structure& lines);
/// Same lines (points, groups and group names) in the same order.
bool sameLines(const app::Structure& a, const app::Structure& b);

}  // namespace kc::ui
