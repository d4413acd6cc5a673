#include <imgui.h>

#include "kc/ui/document.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"

namespace kc::ui {

void markWidget(AppState& state, const char* name) {
  const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  state.widgets[name] = Vec2(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
}

void requestPath(AppState& state, PathPurpose purpose, const std::string& initial) {
  state.pathDialog = purpose;
  state.pathDialogText = initial;
}

float drawMainMenu(AppState& state) {
  if (!ImGui::BeginMainMenuBar()) return 0.0f;
  const bool idle = !state.worker.busy();
  const bool haveSession = state.session != nullptr;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("Open image or session...", "Ctrl+O", false, idle)) requestPath(state, PathPurpose::Open, state.imagePath);
    if (hasRecoveryCopy(state) && ImGui::MenuItem("Open recovery copy", nullptr, false, idle))
      startOpenSession(state, state.recoveryPath);
    if (ImGui::MenuItem("Save session", "Ctrl+S", false, haveSession)) {
      if (state.sessionPath.empty()) requestPath(state, PathPurpose::SaveSession, "untitled.kcw.json");
      else saveSessionFile(state, state.sessionPath);
    }
    if (ImGui::MenuItem("Save session as...", "Ctrl+Shift+S", false, haveSession))
      requestPath(state, PathPurpose::SaveSession, state.sessionPath.empty() ? "untitled.kcw.json" : state.sessionPath);
    if (ImGui::MenuItem("Export PNG...", "Ctrl+E", false, haveSession))
      requestPath(state, PathPurpose::Export, state.exportPath.empty() ? "warped.png" : state.exportPath);
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
  const float height = ImGui::GetWindowSize().y;
  ImGui::EndMainMenuBar();
  return height;
}

}  // namespace kc::ui
