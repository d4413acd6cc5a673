// The file dialogs (native when available, else the in-app browser), the unsaved-changes prompt
// and the handling of dropped files.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>

#include <cstring>
#include <filesystem>

#include "kc/ui/document.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

namespace fs = std::filesystem;

/// Escape went down this frame (not its repeat): it cancels the open dialog or question, as Cancel
/// does. The window holds Escape down for a frame however quickly it was tapped (feedKeys).
bool escapePressed() { return ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false); }

void run(AppState& state, PathPurpose p, const std::string& path) {
  switch (p) {
    case PathPurpose::Open: openAnyFile(state, path); break;
    case PathPurpose::SaveSession: saveSessionFile(state, path); break;
    case PathPurpose::Export:
      state.exportPath = path;
      startExport(state, path);
      break;
    case PathPurpose::LoadCage: loadCageAndBind(state, path); break;
    case PathPurpose::SaveCage: saveCageFile(state, path); break;
    case PathPurpose::None: break;
  }
}

/// The folder the browser lists for a path typed or chosen so far.
std::string folderOf(const std::string& text) {
  std::error_code ec;
  if (text.empty()) return fs::current_path(ec).string();
  if (fs::is_directory(text, ec)) return text;
  const fs::path parent = fs::absolute(text, ec).parent_path();
  return fs::is_directory(parent, ec) ? parent.string() : fs::current_path(ec).string();
}

/// The in-app file browser: folder listing (double-click opens a folder or chooses a file) and
/// the path field, whose text is selected when the dialog opens so typing replaces it.
void browserDialog(AppState& state) {
  static char buffer[1024];  // ImGui needs a stable buffer while the popup is open
  static std::string folder;
  static std::vector<DirEntry> entries;
  auto setFolder = [](const std::string& dir, PathPurpose purpose) {
    std::error_code ec;
    folder = fs::absolute(dir, ec).lexically_normal().string();
    entries = listFolder(folder, purpose);
  };
  if (state.pathDialog != PathPurpose::None && !ImGui::IsPopupOpen("File")) {
    std::string initial = state.pathDialogText;
    setFolder(folderOf(initial), state.pathDialog);
    if (!initial.empty() && fs::path(initial).is_relative()) initial = (fs::path(folder) / initial).string();
    std::strncpy(buffer, initial.c_str(), sizeof buffer - 1);
    buffer[sizeof buffer - 1] = 0;
    ImGui::OpenPopup("File");
  }
  ImGui::SetNextWindowSize(ImVec2(640, 460), ImGuiCond_Appearing);
  if (!ImGui::BeginPopupModal("File", nullptr, ImGuiWindowFlags_NoSavedSettings)) return;
  const PathPurpose purpose = state.pathDialog;
  ImGui::TextUnformatted(dialogTitle(purpose));
  if (button(state, "Up", "Go to the folder above.")) setFolder(fs::path(folder).parent_path().string(), purpose);
  ImGui::SameLine();
  ImGui::TextDisabled("%s", folder.c_str());
  std::string chosen;
  if (ImGui::BeginChild("##files", ImVec2(0, -2.2f * ImGui::GetFrameHeightWithSpacing()), true)) {
    for (const DirEntry& e : entries) {
      const std::string label = e.directory ? "[" + e.name + "]" : e.name;
      const std::string full = (fs::path(folder) / e.name).string();
      if (ImGui::Selectable(label.c_str(), full == buffer, ImGuiSelectableFlags_AllowDoubleClick)) {
        if (!e.directory) {
          std::strncpy(buffer, full.c_str(), sizeof buffer - 1);
          if (ImGui::IsMouseDoubleClicked(0)) chosen = full;
        } else if (ImGui::IsMouseDoubleClicked(0)) {
          setFolder(full, purpose);
          break;
        }
      }
    }
  }
  ImGui::EndChild();
  if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
  ImGui::SetNextItemWidth(-1);
  const bool enter = ImGui::InputText("##path", buffer, sizeof buffer, ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
  tooltip("The file's path: type one, or pick a file above (double-click opens a folder).");
  state.pathDialogText = buffer;  // what the field holds now (the automation state reports it)
  state.pathDialogFocused = ImGui::IsItemActive();
  if (button(state, isSave(purpose) ? "Save##file" : "Open##file", "Use this file.", ImVec2(100, 0)) || enter)
    chosen = buffer;
  ImGui::SameLine();
  const bool cancel =
      button(state, "Cancel##file", "Close without choosing a file (Esc).", ImVec2(100, 0)) || escapePressed();
  if (!chosen.empty() && fs::is_directory(chosen)) {  // a folder typed or picked: list it
    setFolder(chosen, purpose);
    chosen.clear();
  }
  // Saving over a file that exists is asked first (as the desktop's dialogs do).
  std::error_code ec;
  if (!chosen.empty() && isSave(purpose) && chosen != state.replacePath && fs::exists(chosen, ec)) {
    state.replacePath = chosen;
    chosen.clear();
  }
  if (!state.replacePath.empty() && state.replacePath != buffer) state.replacePath.clear();  // another name typed
  if (!state.replacePath.empty()) {  // on the row of Save and Cancel
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s exists.", fs::path(state.replacePath).filename().c_str());
    ImGui::SameLine();
    if (button(state, "Replace it##file", "Write over the file that is there.")) chosen = state.replacePath;
  }
  if (!chosen.empty() || cancel) {
    state.pathDialog = PathPurpose::None;
    state.replacePath.clear();
    ImGui::CloseCurrentPopup();
    if (!chosen.empty()) run(state, purpose, chosen);
    else state.afterSave = nullptr;
  }
  ImGui::EndPopup();
}

/// A native dialog that has closed: run what it chose.
void pollNativeDialog(AppState& state) {
  if (!state.nativeDialog || !state.nativeDialog->done()) return;
  const auto dialog = std::move(state.nativeDialog);
  state.nativeDialog.reset();
  const std::optional<std::string> chosen = dialog->result();
  if (chosen) run(state, dialog->purpose(), *chosen);
  else state.afterSave = nullptr;
}

std::string lowerFirst(std::string s) {
  if (!s.empty()) s[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
  return s;
}

/// A question before an action with a consequence (PendingAction::question): "<what>" or Cancel.
void questionPrompt(AppState& state) {
  const bool asking = state.unsavedPrompt && !state.unsavedPrompt->question.empty();
  if (asking && !ImGui::IsPopupOpen("Before you go on")) ImGui::OpenPopup("Before you go on");
  if (!ImGui::BeginPopupModal("Before you go on", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  if (!asking) {
    ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
    return;
  }
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 36.0f);
  ImGui::TextUnformatted(state.unsavedPrompt->question.c_str());
  ImGui::PopTextWrapPos();
  const std::string go = state.unsavedPrompt->what + "##question";
  if (button(state, go.c_str(), "Go on as described above.")) {
    auto action = std::move(state.unsavedPrompt->run);
    state.unsavedPrompt.reset();
    ImGui::CloseCurrentPopup();
    action(state);
  } else {
    ImGui::SameLine();
    if (button(state, "Cancel##question", "Go back to your work; nothing changes (Esc).") || escapePressed()) {
      state.unsavedPrompt.reset();
      ImGui::CloseCurrentPopup();
    }
  }
  ImGui::EndPopup();
}

/// "Save and <what>", "<what> without saving", "Cancel" before unsaved work would be lost.
void unsavedPrompt(AppState& state) {
  if (state.quitRequested) {
    state.quitRequested = false;
    unlessUnsaved(state, "Quit", [](AppState& st) { st.quitConfirmed = true; });
  }
  const bool asked = state.unsavedPrompt && state.unsavedPrompt->question.empty();
  if (asked && !ImGui::IsPopupOpen("Unsaved changes")) ImGui::OpenPopup("Unsaved changes");
  if (!ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  if (!asked) {  // answered elsewhere (e.g. a second request replaced it)
    ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
    return;
  }
  const PendingAction& pending = *state.unsavedPrompt;
  const bool haveSession = state.session != nullptr, unboundCage = !state.bound && state.cage.size() > 0;
  ImGui::TextUnformatted(unboundCage ? "The cage you drew is not saved." : "The session has unsaved changes.");
  if (hasRecoveryCopy(state))
    ImGui::TextDisabled("An autosaved recovery copy exists (%s);\n%s without saving removes it.", state.recoveryPath.c_str(),
                        pending.what.c_str());
  const std::string save = (unboundCage ? "Save cage and " : "Save and ") + lowerFirst(pending.what);
  const std::string discard = pending.what + " without saving";
  const bool canSave = haveSession || unboundCage;
  if (!canSave) ImGui::BeginDisabled();
  if (button(state, save.c_str(), "Save first (you choose the file if it has none yet), then continue.")) {
    state.afterSave = std::move(state.unsavedPrompt->run);
    state.unsavedPrompt.reset();
    ImGui::CloseCurrentPopup();
    if (unboundCage) requestPath(state, PathPurpose::SaveCage, "cage.json");
    else if (state.sessionPath.empty()) requestPath(state, PathPurpose::SaveSession, proposedSessionPath(state));
    else saveSessionFile(state, state.sessionPath);
  }
  if (!canSave) ImGui::EndDisabled();
  if (state.unsavedPrompt) {
    ImGui::SameLine();
    if (button(state, discard.c_str(), "Continue; the changes since the last save are lost.")) {
      auto action = std::move(state.unsavedPrompt->run);
      state.unsavedPrompt.reset();
      state.unsaved = false;
      ImGui::CloseCurrentPopup();
      action(state);
    }
  }
  if (state.unsavedPrompt) {
    ImGui::SameLine();
    if (button(state, "Cancel##unsaved", "Go back to your work (Esc).") || escapePressed()) {
      state.unsavedPrompt.reset();
      ImGui::CloseCurrentPopup();
    }
  }
  ImGui::EndPopup();
}

}  // namespace

void requestPath(AppState& state, PathPurpose purpose, const std::string& initial) {
  if (state.nativeDialogs && !state.nativeDialog) {
    const std::string program = nativeDialogProgram();
    if (!program.empty()) {
      std::error_code ec;
      const std::string start = initial.empty() || fs::path(initial).is_absolute()
                                    ? initial
                                    : (fs::current_path(ec) / initial).string();
      state.nativeDialog = std::make_shared<NativeDialog>(nativeDialogCommand(program, purpose, start), purpose, state.wakeup);
      return;
    }
  }
  state.pathDialog = purpose;
  state.pathDialogText = initial;
}

void drawDialogs(AppState& state) {
  openDroppedFiles(state);
  pollNativeDialog(state);
  browserDialog(state);
  questionPrompt(state);
  unsavedPrompt(state);
}

}  // namespace kc::ui
