#pragma once
/// Files of the document: open an image or a session, save/load sessions and cages, autosave,
/// and the window title. Errors become messages; a failed load leaves the document untouched.

#include <string>

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Opens a PNG/JPEG (no cage yet: cage tool) or a session (*.kcw.json, on the worker).
/// Returns false with a message on failure.
bool openPath(AppState& state, const std::string& path);
/// Opens an image as a new document with an empty cage (or `cage` when given).
bool openImage(AppState& state, const std::string& path);

/// Saves the session (with the current pose) atomically; clears the unsaved flag.
bool saveSessionFile(AppState& state, const std::string& path);
/// Saves / loads the draft cage (a loaded cage is an undoable edit).
bool saveCageFile(AppState& state, const std::string& path);
bool loadCageFile(AppState& state, const std::string& path);

/// Writes the recovery file (atomic) when there are unsaved changes and the last autosave is
/// older than `interval` seconds. Returns true when a file was written.
bool maybeAutosave(AppState& state, double now, double interval = 60.0);
/// Default recovery path: $XDG_CACHE_HOME or ~/.cache, then kcwarp/recovery.kcw.json.
std::string defaultRecoveryPath();
/// A recovery copy (autosaved unsaved work of a run that did not end normally) exists.
bool hasRecoveryCopy(const AppState& state);
/// Removes the recovery copy (on a normal quit: the user saved or chose to discard).
void discardRecoveryCopy(const AppState& state);

/// "kcwarp — name*" (the star when there are unsaved changes).
std::string windowTitle(const AppState& state);

}  // namespace kc::ui
