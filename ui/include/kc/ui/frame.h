#pragma once
/// One frame of the window's user interface: the menu bar, the side panel with its collapsing
/// headers, the status bar, shortcuts, canvas input and overlays, and the dialogs. The window
/// calls drawFrame() between ImGui::NewFrame() and ImGui::Render(); panel tests call the same
/// function on ImGui's null backend, so they see exactly the layout (and the widget IDs) a person does.

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Width of the side panel in screen pixels.
inline constexpr float kSidePanelWidth = 350.0f;

/// Side panel (right, headers Tools / Weights / Bind / Diagnostics), status bar (bottom) and the
/// canvas rectangle between them, below a menu bar of height `menuHeight`.
void drawLayout(AppState& state, float menuHeight);

/// Draws everything of one frame and applies the user's input; returns true when the display
/// mesh was re-deformed this frame (for the frame log).
bool drawFrame(AppState& state);

}  // namespace kc::ui
