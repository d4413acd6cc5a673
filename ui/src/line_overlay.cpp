// The structure lines over the canvas (canvas.h, drawLinesOverlay): drawn on ImGui's background
// draw list like the other overlays.
#include <imgui.h>

#include <algorithm>
#include <string>
#include <vector>

#include "kc/ui/canvas.h"
#include "overlay_draw.h"

namespace kc::ui {
namespace {

using overlay::im;

/// Colour of a line: ungrouped lines cyan, each parallel group its own colour.
ImU32 lineColor(int group) {
  static constexpr ImU32 kGroups[] = {IM_COL32(255, 110, 200, 255), IM_COL32(160, 255, 80, 255), IM_COL32(255, 215, 50, 255),
                                      IM_COL32(180, 140, 255, 255), IM_COL32(255, 140, 60, 255)};
  if (group < 0) return IM_COL32(70, 220, 255, 255);
  return kGroups[static_cast<std::size_t>(group) % std::size(kGroups)];
}

/// A polyline (screen pixels) with a dark edge so it reads on any picture; `selected` doubles it.
void drawStroke(ImDrawList* dl, const std::vector<ImVec2>& s, ImU32 color, bool selected) {
  const int n = static_cast<int>(s.size());
  dl->AddPolyline(s.data(), n, IM_COL32(20, 20, 28, 220), 0, selected ? 8.0f : 5.0f);
  if (selected) dl->AddPolyline(s.data(), n, IM_COL32(255, 255, 255, 255), 0, 6.0f);
  dl->AddPolyline(s.data(), n, color, 0, 2.5f);
  for (const ImVec2& e : {s.front(), s.back()}) {
    dl->AddCircleFilled(e, 4.5f, IM_COL32(20, 20, 28, 230));
    dl->AddCircleFilled(e, 3.0f, color);
  }
}

std::string groupName(const app::Structure& s, int group) {
  return group >= 0 && group < static_cast<int>(s.groups.size()) ? s.groups[static_cast<std::size_t>(group)] : "";
}

}  // namespace

void drawLinesOverlay(AppState& state) {
  if (state.source.empty()) return;
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const View& view = state.view;
  dl->PushClipRect(im(view.canvasMin), im(view.canvasMin + view.canvasSize), true);
  // Labels after every stroke: a line that crosses another at its middle would cover its label.
  std::vector<overlay::Tag> labels;
  if (state.tool == Tool::Lines) {
    const app::Structure& L = state.lines;
    for (std::size_t k = 0; k < L.lines.size(); ++k) {
      const std::vector<ImVec2> s = {im(view.toScreen(L.lines[k].a)), im(view.toScreen(L.lines[k].b))};
      const bool selected = std::find(state.lineSelection.begin(), state.lineSelection.end(), int(k)) != state.lineSelection.end();
      drawStroke(dl, s, lineColor(L.lines[k].group), selected);
      const std::string name = groupName(L, L.lines[k].group);
      labels.push_back({ImVec2(0.5f * (s[0].x + s[1].x) + 8.0f, 0.5f * (s[0].y + s[1].y) + 4.0f),
                        "line " + std::to_string(k) + (name.empty() ? "" : " (" + name + ")"), lineColor(L.lines[k].group)});
    }
    if (state.lineTool.drawing())  // the line being drawn follows the mouse
      drawStroke(dl, {im(view.toScreen(state.lineTool.start())), im(view.toScreen(state.mouseImage))}, IM_COL32(255, 255, 255, 200), false);
  } else if (state.bound && state.show.lines && !state.bound->lines.empty()) {
    const bool rest = isRestPose(state.pose) || state.pose.size() != static_cast<std::size_t>(state.bound->cage.size());
    for (const BoundLine& l : state.bound->lines) {
      if (l.W.cols() != state.bound->cage.size()) continue;
      const Points P = rest ? l.X : deformPoints(l.W, l.X, state.bound->cage.C, state.pose);
      std::vector<ImVec2> s;
      for (Index i = 0; i < P.rows(); ++i) s.push_back(im(view.toScreen(P.row(i).transpose())));
      if (s.size() < 2) continue;
      drawStroke(dl, s, lineColor(l.group), false);
      labels.push_back({ImVec2(s[s.size() / 2].x + 8.0f, s[s.size() / 2].y + 4.0f), groupName(state.lines, l.group), lineColor(l.group)});
    }
  }
  overlay::drawTags(dl, labels);  // lines drawn close together: their labels moved apart
  dl->PopClipRect();
}

}  // namespace kc::ui
