#pragma once
/// Widgets of the panels with a plain-words tooltip and an automation mark: each records its
/// screen centre under its visible label (AppState::widgets; the text before "##"), so tests
/// click what a person reads, and a clash of IDs between two widgets shows up as a dead click.

#include <imgui.h>

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Shows `text` as a tooltip while the last item is hovered (also when it is disabled).
void tooltip(const char* text);
/// Shows `text` as a tooltip now, wrapped at about 80 characters (long reasons stay on screen).
void showTooltip(const char* text);

/// For the last item drawn (a line of text, a table header): tooltip `tip` and mark it as `name`.
void labelled(AppState& state, const char* name, const char* tip);

/// ImGui::Button + tooltip + mark. Returns true when clicked.
bool button(AppState& state, const char* label, const char* tip, const ImVec2& size = ImVec2(0, 0));
/// ImGui::RadioButton (selected = `active`) + tooltip + mark. Returns true when clicked.
bool radio(AppState& state, const char* label, bool active, const char* tip);
/// ImGui::Checkbox + tooltip + mark. Returns true when toggled.
bool checkbox(AppState& state, const char* label, bool* value, const char* tip);

}  // namespace kc::ui
