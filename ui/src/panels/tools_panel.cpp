#include <imgui.h>

#include <algorithm>
#include <string>

#include "kc/ui/edits.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {

void drawToolsPanel(AppState& state) {
  if (radio(state, "Pose (P)", state.tool == Tool::Pose,
            "Move and turn the cage's points to bend the picture.\nAvailable after Bind."))
    selectTool(state, Tool::Pose);
  ImGui::SameLine();
  const app::BackendCapabilities caps = shownCapabilities(state);
  const bool canPaint = caps.painting;
  if (!canPaint) ImGui::BeginDisabled();
  if (radio(state, "Brush (B)", state.tool == Tool::Brush,
            canPaint ? "Paint how strongly one point pulls on each part of the picture." : caps.why.c_str()))
    selectTool(state, Tool::Brush);
  if (!canPaint) ImGui::EndDisabled();
  ImGui::SameLine();
  if (radio(state, "Cage (C)", state.tool == Tool::Cage,
            "Draw or edit the outline (cage) around the part of the picture you want to bend."))
    selectTool(state, Tool::Cage);
  ImGui::Spacing();
  switch (state.tool) {
    case Tool::Pose:
      ImGui::TextWrapped("Left-drag a point to move it, right-drag to turn it. Shift-click or drag a rectangle to "
                         "select several; right-drag then turns them about the pivot (+), which you can drag. "
                         "Middle-drag or Space+drag pans, the wheel zooms. Hold O to see the original picture.");
      if (button(state, "Reset pose", "Put every point back where it was when you pressed Bind (undoable).")) resetPose(state);
      ImGui::SameLine();
      ImGui::TextDisabled("%zu selected", state.selection.size());
      break;
    case Tool::Brush: {
      ImGui::TextWrapped("Paint the influence of the active point (right-click a point to choose it). "
                         "Ctrl paints the other way. Releasing the mouse updates the picture.");
      float radius = static_cast<float>(state.brush.radius), strength = static_cast<float>(state.brush.strength);
      if (ImGui::SliderFloat("Radius", &radius, 2.0f, 200.0f, "%.0f px", ImGuiSliderFlags_Logarithmic)) state.brush.radius = radius;
      tooltip("Size of the brush, in pixels of the picture.");
      if (ImGui::SliderFloat("Strength", &strength, 0.01f, 1.0f, "%.2f")) state.brush.strength = strength;
      tooltip("How much one dab changes the influence at the brush centre.");
      if (radio(state, "Add", !state.brush.subtract, "Painting makes the active point pull harder here.")) state.brush.subtract = false;
      ImGui::SameLine();
      if (radio(state, "Subtract", state.brush.subtract, "Painting makes the active point pull less here.")) state.brush.subtract = true;
      break;
    }
    case Tool::Cage:
      ImGui::TextWrapped("Click to add points; click the first point to close the cage, then press Bind. Drag a point "
                         "to move it, right-click (or Delete) removes it; click an edge of a closed cage to insert a point.");
      ImGui::Text("%ld points, %s", long(state.cage.size()), state.cage.closed ? "closed" : "open");
      break;
  }
  if (state.bound && state.tool != Tool::Cage) {
    int active = static_cast<int>(state.activeControl);
    ImGui::SetNextItemWidth(120);
    if (ImGui::InputInt("Active point", &active)) {
      state.activeControl = std::clamp<Index>(active, 0, state.boundCage.size() - 1);
      state.selection = {state.activeControl};
      state.pivot.reset();
    }
    tooltip("The point whose influence the heatmap shows and the brush paints (numbers show when you hover a point).");
  }
}

}  // namespace kc::ui
