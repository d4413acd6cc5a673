#include "kc/ui/shortcuts.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <iterator>
#include <utility>
#include <vector>

#include "kc/ui/document.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/line_edits.h"
#include "kc/ui/panels/panels.h"

namespace kc::ui {

void handleShortcuts(AppState& state) {
  const ImGuiIO& io = ImGui::GetIO();
  const std::vector<std::pair<int, int>> fresh = std::exchange(state.tappedKeys, {});
  std::vector<std::pair<int, int>> tapped = std::exchange(state.heldTaps, {});
  tapped.insert(tapped.end(), fresh.begin(), fresh.end());
  state.showOriginal = false;
  state.hideCage = false;
  if (state.pathDialog != PathPurpose::None || state.unsavedPrompt || state.nativeDialog) return;
  if (io.WantTextInput) {
    // The field takes these keys if it is still there next frame (then they are dropped).
    std::copy_if(fresh.begin(), fresh.end(), std::back_inserter(state.heldTaps),
                 [](const std::pair<int, int>& t) { return (t.second & GLFW_MOD_CONTROL) != 0; });
    return;
  }
  // A key counts when ImGui sees it go down this frame or when it was tapped since the last frame
  // (then with the modifiers it was tapped with).
  bool ctrl = io.KeyCtrl, shift = io.KeyShift;
  for (const auto& [key, mods] : tapped) {
    ctrl = ctrl || (mods & GLFW_MOD_CONTROL) != 0;
    shift = shift || (mods & GLFW_MOD_SHIFT) != 0;
  }
  auto pressed = [&tapped](int key) {
    return ImGui::IsKeyPressed(key, false) ||
           std::any_of(tapped.begin(), tapped.end(), [key](const std::pair<int, int>& t) { return t.first == key; });
  };
  if (ctrl) {
    if (pressed(GLFW_KEY_Z)) shift ? redo(state) : undo(state);
    if (pressed(GLFW_KEY_Y)) redo(state);
    if (pressed(GLFW_KEY_S) && state.bound) saveCommand(state, shift);
    if (pressed(GLFW_KEY_E) && state.bound) exportCommand(state, shift);
    if (pressed(GLFW_KEY_O)) requestPath(state, PathPurpose::Open, state.imagePath);
    if (pressed(GLFW_KEY_N)) unlessUnsaved(state, "New", newDocument);
    if (pressed(GLFW_KEY_R)) resetPose(state);
    if (pressed(GLFW_KEY_B)) requestBind(state);
    if (pressed(GLFW_KEY_Q)) state.quitRequested = true;
    return;
  }
  if (state.canvasDrag.button >= 0 && pressed(GLFW_KEY_ESCAPE)) {
    state.poseTool.cancel(state);
    state.brushTool.cancel(state);
    state.cageTool.cancel(state);
    state.lineTool.cancel(state);
    state.rigidTool.cancel(state);
    state.canvasDrag.button = -1;
    return;
  }
  if (state.lineTool.drawing() && pressed(GLFW_KEY_ESCAPE)) state.lineTool.cancel(state);
  if (pressed(GLFW_KEY_P)) selectTool(state, Tool::Pose);
  if (pressed(GLFW_KEY_B)) selectTool(state, Tool::Brush);
  if (pressed(GLFW_KEY_C)) selectTool(state, Tool::Cage);
  if (pressed(GLFW_KEY_L)) selectTool(state, Tool::Lines);
  if (pressed(GLFW_KEY_R)) selectTool(state, Tool::Rigid);
  if (pressed(GLFW_KEY_F)) state.fitPending = true;
  if (pressed(GLFW_KEY_1)) state.view.zoomTo(1.0);
  if (pressed(GLFW_KEY_F1)) state.helpOpen = true;
  state.showOriginal = state.bound && ImGui::IsKeyDown(GLFW_KEY_O);
  state.hideCage = state.bound && !state.showOriginal && state.tool != Tool::Cage && state.tool != Tool::Lines &&
                   ImGui::IsKeyDown(GLFW_KEY_H);  // the tools that show the warp
  if ((pressed(GLFW_KEY_DELETE) || pressed(GLFW_KEY_BACKSPACE)) && state.tool == Tool::Cage) state.cageTool.deleteSelected(state);
  if ((pressed(GLFW_KEY_DELETE) || pressed(GLFW_KEY_BACKSPACE)) && state.tool == Tool::Lines) deleteSelectedLines(state);
}

}  // namespace kc::ui
