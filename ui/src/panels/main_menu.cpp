#include <imgui.h>

#include "kc/ui/document.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {

void markWidget(AppState& state, const char* label) {
  const std::string text(label);
  const std::string name = text.substr(0, text.find("##"));
  if (name.empty()) return;
  const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  state.widgets[name] = Vec2(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
}

float drawMainMenu(AppState& state) {
  if (!ImGui::BeginMainMenuBar()) return 0.0f;
  const bool idle = !state.worker.busy();
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("New", "Ctrl+N", false, idle)) unlessUnsaved(state, "New", newDocument);
    tooltip("Close the picture (asks first when something is unsaved).");
    if (ImGui::MenuItem("Open...", "Ctrl+O", false, idle)) requestPath(state, PathPurpose::Open, state.imagePath);
    tooltip("Open a picture (PNG/JPEG), a saved session (.kcw.json) or a cage (.json). You can also drop files onto the window.");
    if (ImGui::BeginMenu("Open recent", idle && !state.recentFiles.empty())) {
      const std::vector<std::string> recent = state.recentFiles;  // opening reorders the list
      for (const std::string& path : recent)
        if (ImGui::MenuItem(path.c_str())) openAnyFile(state, path);
      ImGui::EndMenu();
    }
    if (hasRecoveryCopy(state) && ImGui::MenuItem("Open recovery copy", nullptr, false, idle))
      unlessUnsaved(state, "Open", [](AppState& st) { openRecoveryCopy(st); });
    ImGui::Separator();
    if (ImGui::MenuItem("Save session", "Ctrl+S", false, state.bound)) saveCommand(state, false);
    tooltip("Save everything (cage, weights, pose) to come back later without binding again.");
    if (ImGui::MenuItem("Save session as...", "Ctrl+Shift+S", false, state.bound)) saveCommand(state, true);
    if (ImGui::MenuItem("Export PNG...", "Ctrl+E", false, state.bound)) exportCommand(state, true);
    tooltip("Write the warped picture, full size, as a PNG.");
    ImGui::Separator();
    if (ImGui::MenuItem("Load cage...")) requestPath(state, PathPurpose::LoadCage, "");
    if (ImGui::MenuItem("Save cage...", nullptr, false, state.cage.size() > 0)) requestPath(state, PathPurpose::SaveCage, "cage.json");
    ImGui::Separator();
    if (ImGui::MenuItem("Quit", "Ctrl+Q")) state.quitRequested = true;
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    const std::string undoLabel = state.undo.canUndo() ? "Undo " + state.undo.nextUndo()->label : "Undo";
    const std::string redoLabel = state.undo.canRedo() ? "Redo " + state.undo.nextRedo()->label : "Redo";
    if (ImGui::MenuItem(undoLabel.c_str(), "Ctrl+Z", false, state.undo.canUndo())) undo(state);
    if (ImGui::MenuItem(redoLabel.c_str(), "Ctrl+Shift+Z", false, state.undo.canRedo())) redo(state);
    ImGui::Separator();
    if (ImGui::MenuItem("Reset pose", "Ctrl+R", false, state.bound)) resetPose(state);
    ImGui::Separator();
    if (ImGui::MenuItem("Bind", "Ctrl+B", false, idle && state.cageValid && !state.source.empty())) startBind(state);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("View")) {
    if (ImGui::MenuItem("Fit picture", "F")) state.fitPending = true;
    if (ImGui::MenuItem("Actual size (100%)", "1")) state.view.zoomTo(1.0);
    ImGui::Separator();
    ImGui::MenuItem("Cage", nullptr, &state.show.cage);
    ImGui::MenuItem("Rest cage", nullptr, &state.show.restCage);
    ImGui::MenuItem("Samples (by kind)", nullptr, &state.show.samples);
    ImGui::MenuItem("Warp mesh", nullptr, &state.show.mesh);
    ImGui::MenuItem("Fold-overs", nullptr, &state.show.foldovers);
    ImGui::MenuItem("Weights heatmap (brush)", nullptr, &state.heat.show);
    ImGui::MenuItem("Weights heatmap (pose)", nullptr, &state.heat.showInPose);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Help")) {
    if (ImGui::MenuItem("How to and shortcuts", "F1")) state.helpOpen = true;
    ImGui::EndMenu();
  }
  const float height = ImGui::GetWindowSize().y;
  ImGui::EndMainMenuBar();
  return height;
}

}  // namespace kc::ui
