#include <imgui.h>

#include <algorithm>
#include <string>

#include "kc/ui/edits.h"
#include "kc/ui/panels/panels.h"

namespace kc::ui {
namespace {

void toolButton(AppState& state, const char* label, Tool tool, const char* id) {
  if (ImGui::RadioButton(label, state.tool == tool)) selectTool(state, tool);
  markWidget(state, id);
}

}  // namespace

void drawToolsPanel(AppState& state) {
  toolButton(state, "Pose (P)", Tool::Pose, "tool_pose");
  ImGui::SameLine();
  const bool canPaint = !state.bound || state.capabilities.painting;
  if (!canPaint) ImGui::BeginDisabled();
  toolButton(state, "Brush (B)", Tool::Brush, "tool_brush");
  if (!canPaint) ImGui::EndDisabled();
  if (!canPaint && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("%s", state.capabilities.why.c_str());
  ImGui::SameLine();
  toolButton(state, "Cage (C)", Tool::Cage, "tool_cage");
  ImGui::Spacing();
  switch (state.tool) {
    case Tool::Pose:
      ImGui::TextWrapped("Left-drag a point to move it, right-drag to rotate it. Shift-click or drag a rectangle to "
                         "select several. Middle-drag or Space+drag pans, the wheel zooms.");
      if (ImGui::Button("Reset pose")) resetPose(state);
      markWidget(state, "reset_pose");
      ImGui::SameLine();
      ImGui::TextDisabled("%zu selected", state.selection.size());
      break;
    case Tool::Brush: {
      ImGui::TextWrapped("Paint the weights of the active control point (right-click a point to choose it). "
                         "Ctrl inverts the brush. Release re-optimizes the painted samples.");
      float radius = static_cast<float>(state.brush.radius), strength = static_cast<float>(state.brush.strength);
      if (ImGui::SliderFloat("Radius", &radius, 2.0f, 200.0f, "%.0f px", ImGuiSliderFlags_Logarithmic)) state.brush.radius = radius;
      if (ImGui::SliderFloat("Strength", &strength, 0.01f, 1.0f, "%.2f")) state.brush.strength = strength;
      if (ImGui::RadioButton("Add", !state.brush.subtract)) state.brush.subtract = false;
      ImGui::SameLine();
      if (ImGui::RadioButton("Subtract", state.brush.subtract)) state.brush.subtract = true;
      break;
    }
    case Tool::Cage:
      ImGui::TextWrapped("Click to add points; click the first point to close the cage. Drag a point to move it, "
                         "right-click (or Delete) removes it; click an edge of a closed cage to insert a point.");
      ImGui::Text("%ld points, %s", long(state.cage.size()), state.cage.closed ? "closed" : "open");
      break;
  }
  if (state.bound && state.tool != Tool::Cage) {
    int active = static_cast<int>(state.activeControl);
    ImGui::SetNextItemWidth(120);
    if (ImGui::InputInt("Active control", &active)) {
      state.activeControl = std::clamp<Index>(active, 0, state.boundCage.size() - 1);
      state.selection = {state.activeControl};
    }
  }
}

}  // namespace kc::ui
