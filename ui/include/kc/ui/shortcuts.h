#pragma once
/// Keyboard shortcuts of the window (ignored while a text field has focus).

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Ctrl+Z undo, Ctrl+Shift+Z / Ctrl+Y redo, Ctrl+S save, Ctrl+Shift+S save as, Ctrl+E export,
/// Ctrl+O open, Ctrl+N new, Ctrl+B bind, Ctrl+R reset pose, Ctrl+Q quit, P/B/C tools, F fit,
/// 1 actual size (100%), hold O to see the original picture, F1 help, Delete removes the selected
/// cage point, Escape cancels a drag.
void handleShortcuts(AppState& state);

}  // namespace kc::ui
