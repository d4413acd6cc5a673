#pragma once
/// Rigid regions in the GUI (thesis 5.4, docs/rigidity.md): what the rigidity brush's release, its
/// panel (Clear rigidity) and undo/redo of a stroke start, and the rigidity shown. The re-solve
/// (app::setRigidity) runs on the worker: progress in the status bar, the window stays
/// responsive. Main thread only.

#include <string>
#include <vector>

#include "kc/app/rigidity.h"
#include "kc/app/session.h"
#include "kc/ui/app_state.h"

namespace kc::ui {

/// Why the rigidity brush cannot be used now, as the greyed tool's tooltip says it (empty when it
/// can): the backend chosen or bound has no rigid regions (LBC), the session has no target weights
/// to restore the unconstrained weights from, or nothing is bound yet.
std::string rigidityProblem(const Document& doc);

/// Sets the session's per-sample rigidity to `rho` (#S, each in [0, 1]) on the worker with
/// app::setRigidity — only the samples within (reach + 5)σ of the old or new region are re-solved —
/// then re-weights the display mesh in the controls whose weights changed. When done, a
/// RigidityEdit (ρ before and after, the changed rows of W before and after) is pushed as `label`
/// and the release → picture time is recorded. Cancel cannot stop the QP half way: the job sees it
/// when the solve ends and then puts the session back as it was (ρ, W, field) and says so.
/// While it runs the tint shows `rho`. Returns false (with a message) when it cannot start.
/// `record` = false (carrying a painted ρ over to a re-bind's samples) pushes no undo entry.
bool startRigidity(AppState& state, std::vector<double> rho, std::string label, bool record = true);

/// A painted ρ carried over to new samples (a re-bind after a line edit): each interior or line
/// sample of `to` takes the ρ of the nearest sample of `from` within 1.5·h (0 when none), and keeps
/// at least `base` (the ρ the new session's rigid polygons give; empty = none). #to entries.
std::vector<double> carryRigidity(const SampleSet& from, const std::vector<double>& rho, const SampleSet& to,
                                  const std::vector<double>& base, double h);

/// Undo (forward = false) or redo of a rigidity stroke: writes edit's ρ and W rows back and
/// re-solves only edit.columns of the field and of the display mesh, on the worker (no QP).
bool startRestoreRigidity(AppState& state, const RigidityEdit& edit, bool forward);

/// Takes all rigidity away (undoable); false when there is none or a job runs.
bool clearRigidity(AppState& state);

/// The status line after a rigidity solve, in plain words: the samples held rigid and the time, or
/// that the solver stopped before it was done.
std::string rigiditySolveSummary(const app::RigidityUpdate& u);
/// The solver's side of it for the diagnostics: region, controls, method and rounds (or ADMM
/// iterations), and whether it converged.
std::string rigiditySolveDetails(const app::RigidityUpdate& u);

/// True when some sample of `rho` is rigid (ρ > 0).
bool anyRigid(const std::vector<double>& rho);

/// The bound session's ρ as shown (#S, or empty: none or nothing bound): while a rigidity job
/// runs the ρ it is solving for (AppState::solvingRigidity), else the snapshot's.
const std::vector<double>& boundRigidity(const Document& doc);

}  // namespace kc::ui
