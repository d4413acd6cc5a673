#pragma once
/// Files of the document: open an image, a session or a cage, save sessions and cages, the
/// unsaved-changes prompt, autosave and the recovery copy, and the window title. Errors become
/// messages; a failed load leaves the document untouched.

#include <functional>
#include <string>

#include "kc/app/image_io.h"
#include "kc/ui/app_state.h"

namespace kc::ui {

/// Opens what a person hands kcwarp (Open dialog, recent list, a file dropped on the window):
/// a session (*.kcw.json, or JSON that is not a cage; on the worker), a cage (JSON with points:
/// put on the current picture and bound right away), else a picture (PNG/JPEG: cage tool).
/// Opening a picture or a session asks first when there is unsaved work. False on failure.
bool openAnyFile(AppState& state, const std::string& path);

/// Opens a PNG/JPEG (no cage yet: cage tool) or a session (*.kcw.json, on the worker), without
/// asking about unsaved work. Returns false with a message on failure.
bool openPath(AppState& state, const std::string& path);
/// Opens an image as a new document with an empty cage, turned as its Exif orientation says
/// unless `orientation` is AsStored (the picture of a recovered cage drawn before kcwarp read it).
bool openImage(AppState& state, const std::string& path, app::ImageOrientation orientation = app::ImageOrientation::Upright);
/// Closes the document: no picture, nothing unsaved (File > New).
void newDocument(AppState& state);

/// Runs `action` now when nothing is unsaved; otherwise opens the unsaved-changes prompt, whose
/// buttons are "Save and <what>", "<what> without saving" and "Cancel".
void unlessUnsaved(AppState& state, std::string what, std::function<void(AppState&)> action);

/// Saves the session (with the current pose) atomically on the worker (jobs.h startSaveSession).
bool saveSessionFile(AppState& state, const std::string& path);
/// File > Save (Ctrl+S) / Save as: saves to the session's file, or asks for one first.
void saveCommand(AppState& state, bool saveAs);
/// The name Save proposes for a session never saved: the picture's, beside it, with .kcw.json
/// (<name>-2.kcw.json, … when that file exists).
std::string proposedSessionPath(const AppState& state);
/// The name "Export to a new file" proposes: a file that does not exist yet — the last export's
/// name, else <picture>-warped.png beside the picture, numbered -2, -3, … past the ones there.
std::string proposedExportPath(const AppState& state);
/// File > Export (Ctrl+E) / export to a new file: writes the export file, or asks for one first.
void exportCommand(AppState& state, bool exportAs);
/// Runs `action` now, or — while a job holds the session (e.g. an autosave) — once it is done.
void whenIdle(AppState& state, std::function<void(AppState&)> action);
/// Runs the first deferred command when the worker is free. Call once per frame.
void runDeferred(AppState& state);
/// Saves / loads the draft cage (a loaded cage is an undoable edit). saveCageFile runs
/// state.afterSave on success.
bool saveCageFile(AppState& state, const std::string& path);
bool loadCageFile(AppState& state, const std::string& path);
/// loadCageFile, then a bind when the cage is valid and a picture is open.
bool loadCageAndBind(AppState& state, const std::string& path);

/// Opens the files dropped onto the window (state.droppedPaths): the first picture or session
/// replaces the document (asking first when work is unsaved), then the first cage is loaded onto
/// that picture (or the open one) and bound. Others are named in a message. Call once per frame.
void openDroppedFiles(AppState& state);

/// Records `path` in the recent files list (and its file, when state.recentFilesPath is set).
void rememberFile(AppState& state, const std::string& path);

inline constexpr double kAutosaveSeconds = 60.0;  ///< How often unsaved work is copied for recovery.

/// Autosave: when there are unsaved changes and the last autosave is older than `interval`
/// seconds, writes the recovery copy: the session (on the worker), or for a cage that is not
/// bound yet the cage and its picture's path (recoveryCagePath). True when a save started.
bool maybeAutosave(AppState& state, double now, double interval = kAutosaveSeconds);
/// Default recovery path: $XDG_CACHE_HOME or ~/.cache, then kcwarp/recovery.kcw.json.
std::string defaultRecoveryPath();
/// Where the recovery copy of an unbound cage goes: recoveryPath with ".cage.json" for ".kcw.json".
std::string recoveryCagePath(const AppState& state);
/// A recovery copy (autosaved unsaved work of a run that did not end normally) exists.
bool hasRecoveryCopy(const AppState& state);
/// Opens the recovery copy (a session, or a picture with its unbound cage).
bool openRecoveryCopy(AppState& state);
/// Removes the recovery copies (on a normal quit: the user saved or chose to discard).
void discardRecoveryCopy(const AppState& state);

/// "kcwarp — name*" (the star when there are unsaved changes).
std::string windowTitle(const AppState& state);

}  // namespace kc::ui
