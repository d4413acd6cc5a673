#pragma once
/// The panels of the window, one function per file (STYLE.md, Immediate-mode UI). Each reads and
/// writes the AppState directly; a change calls one setter or starts one job.

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Menu bar (File, Edit, View, Help); returns its height in pixels.
float drawMainMenu(AppState& state);
/// Tool choice and the active tool's options (pose buttons, brush radius/strength/mode).
void drawToolsPanel(AppState& state);
/// Method radio buttons (QP / QEC / L1), heatmap options and colour bar.
void drawWeightsPanel(AppState& state);
/// The outside-the-cage choice (a combo with plain-words tooltips; setOutsideMode on change).
void drawOutsidePanel(AppState& state);
/// Bind parameters, cage status, Bind button; cage files.
void drawBindPanel(AppState& state);
/// Property table, fold-overs and timings.
void drawDiagnosticsPanel(AppState& state);
/// Bottom bar: latest message, job progress with Cancel, zoom and cursor; error banner on the canvas.
void drawStatusBar(AppState& state, float y, float width, float height);
/// Help > How to: the steps cage → bind → pose → paint → export and the shortcut list (F1).
void drawHelpWindow(AppState& state);
/// The path dialog (open/save/export/cage files) and the unsaved-changes confirmation.
void drawDialogs(AppState& state);

/// Asks for a file path for `purpose` (opens the path dialog prefilled with `initial`).
void requestPath(AppState& state, PathPurpose purpose, const std::string& initial);
/// Records the centre of the last ImGui item under its visible label (the text of `label` before
/// "##") in AppState::widgets, for UI automation: tests and the window test click by label. Not
/// while its window is hidden: a popup that sizes itself is laid out hidden in its first frame and
/// placed in the next, so only then is the item where a click finds it.
void markWidget(AppState& state, const char* label);

}  // namespace kc::ui
