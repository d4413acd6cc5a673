#include <imgui.h>

#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

struct Shortcut {
  const char* keys;
  const char* what;
};

constexpr Shortcut kShortcuts[] = {
    {"Ctrl+O", "Open a picture (PNG/JPEG) or a session (.kcw.json)"},
    {"Ctrl+N", "New: close the document (asks first if unsaved)"},
    {"Ctrl+S / Ctrl+Shift+S", "Save the session / save it under a new name"},
    {"Ctrl+E / Ctrl+Shift+E", "Export the warped picture as PNG / to a new file"},
    {"Ctrl+B", "Bind: compute how the cage points pull on the picture"},
    {"Ctrl+Z / Ctrl+Shift+Z", "Undo / redo"},
    {"Ctrl+R", "Reset the pose"},
    {"Ctrl+Q", "Quit (asks first if unsaved)"},
    {"C", "Cage tool: draw the outline"},
    {"P", "Pose tool: move and turn points"},
    {"B", "Brush tool: paint a point's influence"},
    {"L", "Line tool: draw lines kept straight; Delete removes the selected lines"},
    {"R", "Rigidity brush: paint parts that keep their shape (Ctrl erases)"},
    {"F / 1", "Fit the picture in the window / show it at 100%"},
    {"hold O", "See the original picture (before/after)"},
    {"hold H", "See the warp without the cage, its points and lines"},
    {"Space+drag, middle-drag, wheel", "Pan and zoom"},
    {"Delete", "Remove the selected cage point"},
    {"Escape", "Cancel the drag in progress; close the file dialog or a question without going on"},
    {"F1", "This help"},
};

}  // namespace

void drawHelpWindow(AppState& state) {
  if (!state.helpOpen) return;
  ImGui::SetNextWindowSize(ImVec2(560, 520), ImGuiCond_Appearing);
  const ImVec2 centre = ImGui::GetMainViewport()->GetCenter();
  ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  if (!ImGui::Begin("Help##window", &state.helpOpen, ImGuiWindowFlags_NoSavedSettings)) {
    ImGui::End();
    return;
  }
  ImGui::TextUnformatted("How to warp a picture");
  ImGui::Separator();
  ImGui::TextWrapped("1. Open your picture: File > Open, or drop it onto the window.");
  ImGui::TextWrapped("2. Cage: click around the part you want to bend (a character, an arm...). "
                     "Click the first point again to close the outline.");
  ImGui::TextWrapped("3. Bind: press the Bind button (Ctrl+B). kcwarp computes how strongly each cage "
                     "point pulls on every part of the picture; the progress shows at the bottom. "
                     "Weights KC (the default) are smooth and paintable; LBC makes each point pull only "
                     "on the part of the shape near it (no brush, and the outside is kept or pinned).");
  ImGui::TextWrapped("4. Pose: drag a point to move it, right-drag to turn it. Select several (Shift-click or a "
                     "rectangle) and right-drag to turn them together about the + pivot.");
  ImGui::TextWrapped("5. Paint (optional): with the Brush, right-click a point, then paint where it should pull "
                     "harder (Ctrl: less).");
  ImGui::TextWrapped("Lines (optional, L): draw lines that must stay straight (a horizon, a sword); select several "
                     "and press Make parallel to keep them parallel. They stay straight when you move points; "
                     "turning points can bend them. Each change binds again.");
  ImGui::TextWrapped("Rigid parts (optional, R): paint over a part that should keep its shape (a head, a wheel); it "
                     "turns cyan, and on release kcwarp computes the weights around it again. Ctrl erases.");
  ImGui::TextWrapped("6. Export: File > Export PNG (Ctrl+E). Save the session (Ctrl+S) to come back later.");
  ImGui::Spacing();
  ImGui::TextUnformatted("Shortcuts");
  ImGui::Separator();
  if (ImGui::BeginTable("shortcuts", 2, ImGuiTableFlags_RowBg)) {
    // Keys as wide as they need; descriptions take the rest of the window and wrap in it.
    ImGui::TableSetupColumn("keys", ImGuiTableColumnFlags_WidthFixed);
    ImGui::TableSetupColumn("what", ImGuiTableColumnFlags_WidthStretch);
    for (const Shortcut& s : kShortcuts) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(s.keys);
      ImGui::TableNextColumn();
      ImGui::TextWrapped("%s", s.what);
    }
    ImGui::EndTable();
  }
  if (button(state, "Close##help", "Close this help (F1 opens it again).")) state.helpOpen = false;
  ImGui::End();
}

}  // namespace kc::ui
