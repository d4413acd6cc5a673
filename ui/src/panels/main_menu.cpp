#include <imgui.h>
#include <imgui_internal.h>

#include <string>

#include "kc/ui/document.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {

void markWidget(AppState& state, const char* label) {
  const std::string text(label);
  const std::string name = text.substr(0, text.find("##"));
  if (name.empty() || ImGui::GetCurrentWindowRead()->Hidden) return;
  const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  state.widgets[name] = Vec2(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
}

float drawMainMenu(AppState& state) {
  if (!ImGui::BeginMainMenuBar()) return 0.0f;
  const bool idle = !state.worker.busy();
  const bool fileMenu = ImGui::BeginMenu("File");
  markWidget(state, "File");
  tooltip("Open pictures, sessions and cages; save; export the warped picture.");
  if (fileMenu) {
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
    if (hasRecoveryCopy(state)) {
      if (ImGui::MenuItem("Open recovery copy", nullptr, false, idle))
        unlessUnsaved(state, "Open", [](AppState& st) { openRecoveryCopy(st); });
      tooltip("Open the copy of unsaved work that kcwarp kept when it last closed without saving.");
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Save session", "Ctrl+S", false, state.bound != nullptr)) saveCommand(state, false);
    tooltip("Save everything (cage, weights, pose) to come back later without binding again.");
    if (ImGui::MenuItem("Save session as...", "Ctrl+Shift+S", false, state.bound != nullptr)) saveCommand(state, true);
    tooltip("Save everything to a new file name.");
    // The same commands as the shortcuts shown beside them (shortcuts.cpp).
    if (ImGui::MenuItem("Export PNG", "Ctrl+E", false, state.bound != nullptr)) exportCommand(state, false);
    markWidget(state, "Export PNG");
    const std::string again = "Write the warped picture, full size, again to " + state.exportPath + " (replacing it).";
    tooltip(state.exportPath.empty() ? "Write the warped picture, full size, as a PNG (you choose the file)." : again.c_str());
    if (ImGui::MenuItem("Export PNG as...", "Ctrl+Shift+E", false, state.bound != nullptr)) exportCommand(state, true);
    markWidget(state, "Export PNG as...");
    tooltip("Write the warped picture, full size, as a PNG to a new file.");
    ImGui::Separator();
    if (ImGui::MenuItem("Load cage...")) requestPath(state, PathPurpose::LoadCage, "");
    tooltip("Read a cage outline from a JSON file (it is bound right away).");
    if (ImGui::MenuItem("Save cage...", nullptr, false, state.cage.size() > 0)) requestPath(state, PathPurpose::SaveCage, "cage.json");
    tooltip("Write the cage outline to a JSON file.");
    ImGui::Separator();
    if (ImGui::MenuItem("Quit", "Ctrl+Q")) state.quitRequested = true;
    tooltip("Close kcwarp (asks first when something is unsaved).");
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    const std::string undoLabel = state.undo.canUndo() ? "Undo " + state.undo.nextUndo()->label : "Undo";
    const std::string redoLabel = state.undo.canRedo() ? "Redo " + state.undo.nextRedo()->label : "Redo";
    if (ImGui::MenuItem(undoLabel.c_str(), "Ctrl+Z", false, state.undo.canUndo())) undo(state);
    tooltip("Take back the last change (a pose, a brush stroke, a method switch, a cage edit).");
    if (ImGui::MenuItem(redoLabel.c_str(), "Ctrl+Shift+Z", false, state.undo.canRedo())) redo(state);
    tooltip("Do again what Undo took back.");
    ImGui::Separator();
    if (ImGui::MenuItem("Reset pose", "Ctrl+R", false, state.bound != nullptr)) resetPose(state);
    tooltip("Put every cage point back where it was when you pressed Bind (undoable).");
    ImGui::Separator();
    if (ImGui::MenuItem("Bind", "Ctrl+B", false, idle && state.cageValid && !state.source.empty())) requestBind(state);
    tooltip("Compute how the cage points pull on the picture; then drag a point to deform it.");
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("View")) {
    if (ImGui::MenuItem("Fit picture", "F")) state.fitPending = true;
    tooltip("Zoom so the whole picture fits the window.");
    if (ImGui::MenuItem("Actual size (100%)", "1")) state.view.zoomTo(1.0);
    tooltip("One picture pixel per screen pixel.");
    ImGui::Separator();
    ImGui::MenuItem("Cage", nullptr, &state.show.cage);
    tooltip("Show the cage (its outline and points) over the picture.");
    ImGui::MenuItem("Rest cage", nullptr, &state.show.restCage);
    tooltip("Also show where the cage was before you moved its points.");
    ImGui::MenuItem("Lines", nullptr, &state.show.lines);
    tooltip("Show the lines kept straight (line tool, L) over the warped picture; each parallel group has its own colour.");
    ImGui::MenuItem("Rigid regions", nullptr, &state.show.rigid);
    tooltip("Tint the parts painted rigid (rigidity brush, R) in cyan and outline the rigid shapes of a structure file.");
    ImGui::MenuItem("Samples", nullptr, &state.show.samples);
    tooltip("Show the points the weights were computed at, with a legend: coloured by their spacing where it varies "
            "(closer where the cage is narrow), else by kind (cage point, edge, inside, outside).");
    ImGui::MenuItem("Samples by spacing", nullptr, &state.show.sampleSpacing, state.show.samples);
    tooltip("Colour the samples by how close together they lie (on), or by kind (off).");
    ImGui::MenuItem("Warp mesh", nullptr, &state.show.mesh);
    tooltip("Show the grid of triangles the picture is drawn with.");
    ImGui::MenuItem("Fold-overs", nullptr, &state.show.foldovers);
    tooltip("Mark in red the places where the pose folds the picture over itself.");
    ImGui::MenuItem("Weights heatmap (brush)", nullptr, &state.heat.show);
    tooltip("Colour the picture by the active point's influence while the brush tool is on.");
    ImGui::MenuItem("Weights heatmap (pose)", nullptr, &state.heat.showInPose);
    tooltip("Colour the picture by the active point's influence while posing too.");
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Help")) {
    if (ImGui::MenuItem("How to and shortcuts", "F1")) state.helpOpen = true;
    tooltip("The steps from cage to export, and every keyboard shortcut.");
    ImGui::EndMenu();
  }
  const float height = ImGui::GetWindowSize().y;
  ImGui::EndMainMenuBar();
  return height;
}

}  // namespace kc::ui
