#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "kc/ui/edits.h"
#include "kc/ui/line_edits.h"
#include "kc/ui/rigidity_edits.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

constexpr const char* kWhatHolds =
    "What holds: when you move points, each line stays straight and the lines of a parallel group stay "
    "parallel. Turning points (right-drag) can bend them, and lines stretch with the picture.";

/// The line tool's options: how to draw, what holds, the list of lines, parallel groups, delete.
void drawLinesSection(AppState& state) {
  ImGui::TextWrapped("Drag across the picture (or click at both ends) to draw a line kcwarp keeps straight. Click a "
                     "line to select it (Shift: several); right-click or Delete removes it. Adding or removing a "
                     "line binds again.");
  ImGui::TextDisabled("What holds? (hover)");
  labelled(state, "What holds? (hover)", kWhatHolds);
  const app::Structure& L = state.lines;
  if (L.lines.empty()) ImGui::TextDisabled("No lines yet.");
  for (std::size_t k = 0; k < L.lines.size(); ++k) {
    const StructureLine& l = L.lines[k];
    const std::string group = l.group >= 0 ? " - parallel: " + L.groups[static_cast<std::size_t>(l.group)] : "";
    const std::string label = "line " + std::to_string(k) + group + "##line" + std::to_string(k);
    auto& sel = state.lineSelection;
    const auto it = std::find(sel.begin(), sel.end(), static_cast<int>(k));
    if (ImGui::Selectable(label.c_str(), it != sel.end())) {
      if (!ImGui::GetIO().KeyShift) sel = {static_cast<int>(k)};
      else if (it == sel.end()) sel.push_back(static_cast<int>(k));
      else sel.erase(it);
    }
    char tip[160];
    std::snprintf(tip, sizeof tip, "%.0f px long. Click to select it, Shift-click to select several.", l.length());
    labelled(state, label.c_str(), tip);
  }
  const bool busy = state.bound && state.worker.busy();
  const std::size_t n = state.lineSelection.size();
  char name[64];
  std::snprintf(name, sizeof name, "%s", state.lineGroupName.c_str());
  ImGui::SetNextItemWidth(140);
  if (ImGui::InputText("Group name", name, sizeof name)) state.lineGroupName = name;
  labelled(state, "Group name", "The name of the parallel group \"Make parallel\" puts the selected lines in (an existing "
                                "name adds them to that group).");
  if (busy || n < 2) ImGui::BeginDisabled();
  if (button(state, "Make parallel", n < 2 ? "Select two or more lines (Shift-click) to keep them parallel."
                                           : "Keep the selected lines parallel to each other when you move points. They must "
                                             "be drawn within 5 degrees of each other."))
    groupSelectedLines(state, state.lineGroupName);
  if (busy || n < 2) ImGui::EndDisabled();
  ImGui::SameLine();
  if (busy || n == 0) ImGui::BeginDisabled();
  if (button(state, "Not parallel", "The selected lines leave their parallel group (they still stay straight)."))
    ungroupSelectedLines(state);
  ImGui::SameLine();
  if (button(state, "Delete line", "Remove the selected lines (Delete key); kcwarp binds again without them."))
    deleteSelectedLines(state);
  if (busy || n == 0) ImGui::EndDisabled();
}

/// The rigidity brush's options: radius, softness, strength, paint or erase, clear, the last time.
void drawRigiditySection(AppState& state) {
  ImGui::TextWrapped("Paint over a part that should keep its shape (a head, a wheel): it turns cyan. Ctrl or Erase "
                     "takes it away. Releasing the mouse computes the weights again around the painted part only.");
  RigidBrushSettings& b = state.rigidBrush;
  float radius = static_cast<float>(b.radius), softness = static_cast<float>(b.softness), strength = static_cast<float>(b.strength);
  if (ImGui::SliderFloat("Radius##rigid", &radius, 2.0f, 200.0f, "%.0f px", ImGuiSliderFlags_Logarithmic)) b.radius = radius;
  labelled(state, "Radius", "Size of the rigidity brush, in pixels of the picture.");
  if (ImGui::SliderFloat("Softness##rigid", &softness, 0.0f, 1.0f, "%.2f")) b.softness = softness;
  labelled(state, "Softness", "How gradually the brush fades out towards its rim: 0 paints a hard-edged disc, 1 fades from the "
                              "centre. The inner ring shows where the fading starts.");
  if (ImGui::SliderFloat("Strength##rigid", &strength, 0.05f, 1.0f, "%.2f")) b.strength = strength;
  labelled(state, "Strength", "How rigid the painted part becomes: 1 keeps its shape as well as the moved points allow, lower "
                              "values let it bend part of the way. When erasing, how much of the rigidity is taken away.");
  if (radio(state, "Paint##rigid", !b.erase, "Painting makes the part under the brush keep its shape.")) b.erase = false;
  ImGui::SameLine();
  if (radio(state, "Erase##rigid", b.erase, "Painting lets the part under the brush bend freely again (Ctrl does this too).")) b.erase = true;
  const std::vector<double>& rho = boundRigidity(state);
  const bool any = anyRigid(rho);
  const bool busy = !state.session;
  if (!any || busy) ImGui::BeginDisabled();
  if (button(state, "Clear rigidity", !any ? "Nothing is rigid yet." : "Let the whole picture bend freely again (undoable)."))
    clearRigidity(state);
  if (!any || busy) ImGui::EndDisabled();
  const long rigid = std::count_if(rho.begin(), rho.end(), [](double r) { return r > 0.0; });
  char text[160];
  if (state.timings.releaseToPictureMs > 0.0)
    std::snprintf(text, sizeof text, "%ld samples rigid. Last change: %.0f ms to the picture.", rigid, state.timings.releaseToPictureMs);
  else
    std::snprintf(text, sizeof text, "%ld samples rigid.", rigid);
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped("%s", text);
  ImGui::PopStyleColor();
  labelled(state, "Rigid samples", "How many of the points the weights are computed at are painted rigid, and the time from the last "
                                   "release of the mouse (or re-computation) to the updated picture.");
  if (!state.lines.rigid.empty())
    ImGui::TextWrapped("%zu rigid shape(s) from the structure file are outlined in cyan.", state.lines.rigid.size());
}

}  // namespace

void drawToolsPanel(AppState& state) {
  if (radio(state, "Pose (P)", state.tool == Tool::Pose,
            "Move and turn the cage's points to bend the picture. Available after Bind."))
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
  if (!caps.lines) ImGui::BeginDisabled();
  if (radio(state, "Lines (L)", state.tool == Tool::Lines,
            caps.lines ? "Draw lines that stay straight when you move points (a horizon, a sword, a table edge)."
                       : "Lines are kept straight by KC weights only: choose KC in the Bind panel."))
    selectTool(state, Tool::Lines);
  if (!caps.lines) ImGui::EndDisabled();
  ImGui::SameLine();
  const std::string rigidProblem = rigidityProblem(state);
  if (!rigidProblem.empty()) ImGui::BeginDisabled();
  const std::string rigidTip = rigidProblem.empty() ? std::string("Paint the parts that should keep their shape when you move points "
                                                                  "(a head, a wheel); they bend as little as the points allow.")
                                                    : "Not available: " + rigidProblem + ".";
  if (radio(state, "Rigid (R)", state.tool == Tool::Rigid, rigidTip.c_str())) selectTool(state, Tool::Rigid);
  if (!rigidProblem.empty()) ImGui::EndDisabled();
  ImGui::Spacing();
  switch (state.tool) {
    case Tool::Pose:
      ImGui::TextWrapped("Left-drag a point to move it, right-drag to turn it. Shift-click or drag a rectangle to "
                         "select several; right-drag then turns them about the pivot (+), which you can drag. "
                         "Middle-drag or Space+drag pans, the wheel zooms. Hold O to see the original picture, H to hide the cage.");
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
      if (cageIsEdgeGraph(state.cage))
        ImGui::TextWrapped("%ld points, %zu edges: an edge graph from a cage file (closed loops and sticks). Drag "
                           "points to move them; its edges are edited in the file.",
                           long(state.cage.size()), state.cage.edges.size());
      else
        ImGui::Text("%ld points, %s", long(state.cage.size()), state.cage.closed ? "closed" : "open");
      break;
    case Tool::Lines:
      drawLinesSection(state);
      break;
    case Tool::Rigid:
      drawRigiditySection(state);
      break;
  }
  if (state.bound && state.tool != Tool::Cage && state.tool != Tool::Lines && state.tool != Tool::Rigid) {
    int active = static_cast<int>(state.activeControl);
    ImGui::SetNextItemWidth(120);
    if (ImGui::InputInt("Active point", &active)) {
      state.activeControl = std::clamp<Index>(active, 0, state.bound->cage.size() - 1);
      state.selection = {state.activeControl};
      state.pivot.reset();
    }
    tooltip("The point whose influence the heatmap shows and the brush paints (numbers show when you hover a point).");
  }
}

}  // namespace kc::ui
