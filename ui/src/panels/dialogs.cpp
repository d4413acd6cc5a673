#include <imgui.h>

#include <cstring>

#include "kc/ui/document.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"

namespace kc::ui {
namespace {

const char* title(PathPurpose p) {
  switch (p) {
    case PathPurpose::Open: return "Open image (PNG/JPEG) or session (*.kcw.json)";
    case PathPurpose::SaveSession: return "Save session as";
    case PathPurpose::Export: return "Export warped PNG";
    case PathPurpose::LoadCage: return "Load cage (JSON)";
    case PathPurpose::SaveCage: return "Save cage (JSON)";
    case PathPurpose::None: break;
  }
  return "";
}

void run(AppState& state, PathPurpose p, const std::string& path) {
  switch (p) {
    case PathPurpose::Open: openPath(state, path); break;
    case PathPurpose::SaveSession: saveSessionFile(state, path); break;
    case PathPurpose::Export:
      state.exportPath = path;
      startExport(state, path);
      break;
    case PathPurpose::LoadCage: loadCageFile(state, path); break;
    case PathPurpose::SaveCage: saveCageFile(state, path); break;
    case PathPurpose::None: break;
  }
}

void pathDialog(AppState& state) {
  static char buffer[1024];  // ImGui needs a stable buffer while the popup is open
  if (state.pathDialog != PathPurpose::None && !ImGui::IsPopupOpen("File")) {
    std::strncpy(buffer, state.pathDialogText.c_str(), sizeof buffer - 1);
    buffer[sizeof buffer - 1] = 0;
    ImGui::OpenPopup("File");
  }
  ImGui::SetNextWindowSize(ImVec2(560, 0), ImGuiCond_Appearing);
  if (!ImGui::BeginPopupModal("File", nullptr, ImGuiWindowFlags_NoSavedSettings)) return;
  ImGui::TextUnformatted(title(state.pathDialog));
  if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
  ImGui::SetNextItemWidth(-1);
  const bool enter = ImGui::InputText("##path", buffer, sizeof buffer, ImGuiInputTextFlags_EnterReturnsTrue);
  if (ImGui::Button("OK", ImVec2(100, 0)) || enter) {
    const PathPurpose p = state.pathDialog;
    state.pathDialog = PathPurpose::None;
    ImGui::CloseCurrentPopup();
    if (buffer[0]) run(state, p, buffer);
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel", ImVec2(100, 0)) || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) {
    state.pathDialog = PathPurpose::None;
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

void quitDialog(AppState& state) {
  if (state.quitRequested && !state.unsaved) {
    state.quitConfirmed = true;
    return;
  }
  if (state.quitRequested && !ImGui::IsPopupOpen("Unsaved changes")) ImGui::OpenPopup("Unsaved changes");
  if (!ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  ImGui::TextUnformatted("The session has unsaved changes. Quit anyway?");
  if (!state.recoveryPath.empty()) ImGui::TextDisabled("(A recovery copy is autosaved to %s.)", state.recoveryPath.c_str());
  if (ImGui::Button("Save and quit") && state.session) {
    if (state.sessionPath.empty()) {
      state.quitRequested = false;
      ImGui::CloseCurrentPopup();
      requestPath(state, PathPurpose::SaveSession, "untitled.kcw.json");
    } else if (saveSessionFile(state, state.sessionPath)) {
      state.quitConfirmed = true;
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("Quit without saving")) state.quitConfirmed = true;
  markWidget(state, "quit_discard");
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) {
    state.quitRequested = false;
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

}  // namespace

void drawDialogs(AppState& state) {
  pathDialog(state);
  quitDialog(state);
}

}  // namespace kc::ui
