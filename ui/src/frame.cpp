#include "kc/ui/frame.h"

#include <imgui.h>

#include "kc/ui/canvas.h"
#include "kc/ui/document.h"
#include "kc/ui/edits.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/shortcuts.h"

namespace kc::ui {

void drawLayout(AppState& state, float menuHeight) {
  const ImGuiIO& io = ImGui::GetIO();
  const float statusHeight = ImGui::GetFrameHeight() + 12.0f;
  const float panelHeight = io.DisplaySize.y - menuHeight - statusHeight;
  layoutCanvas(state, Vec2(0, menuHeight), Vec2(io.DisplaySize.x - kSidePanelWidth, panelHeight));
  // Before the panels: they show this frame's clicks (a selection's count), not the last frame's.
  handleCanvasInput(state);
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - kSidePanelWidth, menuHeight));
  ImGui::SetNextWindowSize(ImVec2(kSidePanelWidth, panelHeight));
  ImGui::Begin("##side", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoSavedSettings);
  if (ImGui::CollapsingHeader("Tools", ImGuiTreeNodeFlags_DefaultOpen)) drawToolsPanel(state);
  if (ImGui::CollapsingHeader("Weights", ImGuiTreeNodeFlags_DefaultOpen)) drawWeightsPanel(state);
  if (ImGui::CollapsingHeader("Outside", ImGuiTreeNodeFlags_DefaultOpen)) drawOutsidePanel(state);
  if (ImGui::CollapsingHeader("Bind", ImGuiTreeNodeFlags_DefaultOpen)) drawBindPanel(state);
  if (ImGui::CollapsingHeader("Diagnostics", ImGuiTreeNodeFlags_DefaultOpen)) drawDiagnosticsPanel(state);
  ImGui::End();
  drawStatusBar(state, io.DisplaySize.y - statusHeight, io.DisplaySize.x, statusHeight);
}

bool drawFrame(AppState& state) {
  state.widgets.clear();  // the widgets drawn this frame report where they are
  runDeferred(state);
  const float menuHeight = drawMainMenu(state);
  drawLayout(state, menuHeight);
  handleShortcuts(state);
  const bool deformed = updateDeformation(state);
  drawCanvasOverlay(state);
  drawHelpWindow(state);
  drawDialogs(state);
  return deformed;
}

}  // namespace kc::ui
