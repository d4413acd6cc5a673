#include <imgui.h>

#include <cmath>
#include <cstdio>

#include "kc/app/diagnostics.h"
#include "kc/app/heatmap.h"
#include "kc/ui/heat_field.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

/// A vertical-tick horizontal colour bar of the heatmap range, with end and middle labels.
void colorBar(const AppState& state) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x - 8.0f, height = 14.0f;
  const int steps = 64;
  for (int k = 0; k < steps; ++k) {
    const Rgba c = app::heatColor((k + 0.5) / steps);
    dl->AddRectFilled({p.x + width * k / steps, p.y}, {p.x + width * (k + 1) / steps + 1, p.y + height},
                      IM_COL32(c.r, c.g, c.b, 255));
  }
  dl->AddRect(p, {p.x + width, p.y + height}, IM_COL32(0, 0, 0, 255));
  const HeatRange r{state.heatLow, state.heatHigh, state.heat.log};
  // The level a person sees move: weight kDragWeight moves a pixel kVisibleShift px under a
  // kDragPixels drag of the point. A white tick edged in black, reaching a little past the bar.
  const double drag = heatPosition(app::kDragWeight, r);
  const bool tick = r.high > app::kDragWeight && r.low < app::kDragWeight;
  if (tick) {
    const float x = p.x + width * static_cast<float>(drag);
    dl->AddRectFilled({x - 2.0f, p.y - 3.0f}, {x + 2.0f, p.y + height + 3.0f}, IM_COL32(0, 0, 0, 255));
    dl->AddLine({x, p.y - 2.0f}, {x, p.y + height + 2.0f}, IM_COL32(255, 255, 255, 255), 2.0f);
  }
  ImGui::Dummy({width, height});
  if (tick && ImGui::IsItemHovered()) {
    ImGui::SetTooltip("The tick marks weight %.4g: where the weight is at least that, dragging the point %.0f px moves the "
                      "picture %.1f px or more.", app::kDragWeight, app::kDragPixels, app::kVisibleShift);
  }
  const double mid = r.log ? std::sqrt(r.low * r.high) : 0.5 * (r.low + r.high);
  // Round-off (an LBC weight of −2.6e-17) is labelled 0, not as a number a person must decode.
  auto label = [](char (&out)[32], double v) { std::snprintf(out, sizeof out, "%.3g", std::abs(v) < 1e-12 ? 0.0 : v); };
  char lo[32], md[32], hi[32];
  label(lo, r.low);
  label(md, mid);
  label(hi, r.high);
  const float x0 = ImGui::GetCursorPosX();
  ImGui::TextUnformatted(lo);
  ImGui::SameLine(x0 + width * 0.5f - ImGui::CalcTextSize(md).x * 0.5f);
  ImGui::TextUnformatted(md);
  ImGui::SameLine(x0 + width - ImGui::CalcTextSize(hi).x);
  ImGui::TextUnformatted(hi);
}

void methodControl(AppState& state) {
  // One control for the method: before a bind it is the bind's method, after it switching
  // re-optimizes the bound session (painted targets are kept) and the next bind uses it too.
  const Method current = state.bound ? state.bound->method : state.bindParams.kc.method;
  const app::BackendCapabilities caps = shownCapabilities(state);
  const bool canSwitch = caps.methods && (!state.bound || (state.session != nullptr && !state.worker.busy()));
  const struct {
    const char* label;
    Method method;
    const char* tip;
  } methods[] = {
      {"QP", Method::QP, "Smooth influence, not negative at the sample points (between them it may dip a little below 0, as the colour bar shows) (recommended)."},
      {"QEC", Method::QEC, "Fastest; influences may turn slightly negative, so far parts can move the wrong way."},
      {"L1", Method::L1, "Sparse: each part of the picture follows fewer points, more locally."},
  };
  ImGui::TextUnformatted("Method");
  tooltip("How the influence of each cage point is spread over the picture.");
  for (const auto& m : methods) {
    ImGui::SameLine();
    if (!canSwitch) ImGui::BeginDisabled();
    if (radio(state, m.label, current == m.method, caps.methods ? m.tip : caps.why.c_str())) {
      state.bindParams.kc.method = m.method;
      if (state.bound) switchMethod(state, m.method);
    }
    if (!canSwitch) ImGui::EndDisabled();
  }
}

}  // namespace

void drawWeightsPanel(AppState& state) {
  methodControl(state);
  if (!state.bound) {
    ImGui::TextDisabled("Bind a cage to see and edit its influence.");
    return;
  }
  // The picture shows the heatmap in the Pose and Brush tools only (the others draw their own
  // overlays: cage, lines, rigidity); elsewhere the box is shown off and disabled, not ticked.
  const bool heatTool = state.tool == Tool::Pose || state.tool == Tool::Brush;
  bool noHeat = false;
  ImGui::BeginDisabled(!heatTool);
  checkbox(state, "Heatmap", !heatTool ? &noHeat : state.tool == Tool::Pose ? &state.heat.showInPose : &state.heat.show,
           heatTool ? "Colour the picture by how strongly the active point pulls on it."
                    : "Colour the picture by how strongly the active point pulls on it (in the Pose and Brush tools).");
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (radio(state, "Linear", !state.heat.log, "Colours proportional to the influence.")) state.heat.log = false;
  ImGui::SameLine();
  if (radio(state, "Log", state.heat.log, "Logarithmic colours: shows small influences far away.")) state.heat.log = true;
  ImGui::SliderFloat("Opacity", &state.heat.opacity, 0.0f, 1.0f, "%.2f");
  tooltip("How strongly the heatmap covers the picture.");
  if (state.activeControl >= 0) {
    ImGui::Text("Influence of point %ld", long(state.activeControl));
    colorBar(state);
  } else {
    ImGui::TextDisabled("Select a point to see its influence.");
  }
}

}  // namespace kc::ui
