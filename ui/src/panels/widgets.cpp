#include "kc/ui/panels/widgets.h"

#include "kc/ui/panels/panels.h"

namespace kc::ui {

void showTooltip(const char* text) {
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 45.0f);
  ImGui::TextUnformatted(text);
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

void tooltip(const char* text) {
  if (text && *text && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) showTooltip(text);
}

void labelled(AppState& state, const char* name, const char* tip) {
  tooltip(tip);
  markWidget(state, name);
}

bool button(AppState& state, const char* label, const char* tip, const ImVec2& size) {
  const bool clicked = ImGui::Button(label, size);
  tooltip(tip);
  markWidget(state, label);
  return clicked;
}

bool radio(AppState& state, const char* label, bool active, const char* tip) {
  const bool clicked = ImGui::RadioButton(label, active);
  tooltip(tip);
  markWidget(state, label);
  return clicked;
}

bool checkbox(AppState& state, const char* label, bool* value, const char* tip) {
  const bool changed = ImGui::Checkbox(label, value);
  tooltip(tip);
  markWidget(state, label);
  return changed;
}

}  // namespace kc::ui
