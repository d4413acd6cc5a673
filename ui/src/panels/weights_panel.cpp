#include <imgui.h>

#include <cmath>
#include <cstdio>

#include "kc/app/heatmap.h"
#include "kc/ui/heat_field.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"

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
  ImGui::Dummy({width, height});
  const HeatRange r{state.heatLow, state.heatHigh, state.heat.log};
  const double mid = r.log ? std::sqrt(r.low * r.high) : 0.5 * (r.low + r.high);
  char lo[32], md[32], hi[32];
  std::snprintf(lo, sizeof lo, "%.3g", r.low);
  std::snprintf(md, sizeof md, "%.3g", mid);
  std::snprintf(hi, sizeof hi, "%.3g", r.high);
  const float x0 = ImGui::GetCursorPosX();
  ImGui::TextUnformatted(lo);
  ImGui::SameLine(x0 + width * 0.5f - ImGui::CalcTextSize(md).x * 0.5f);
  ImGui::TextUnformatted(md);
  ImGui::SameLine(x0 + width - ImGui::CalcTextSize(hi).x);
  ImGui::TextUnformatted(hi);
}

}  // namespace

void drawWeightsPanel(AppState& state) {
  if (!state.bound) {
    ImGui::TextDisabled("Bind a cage to see and edit weights.");
    return;
  }
  ImGui::TextUnformatted("Method");
  ImGui::SameLine();
  const bool canSwitch = state.session != nullptr && !state.worker.busy() && state.capabilities.methods;
  const struct {
    const char* label;
    Method method;
    const char* id;
  } methods[] = {{"QP", Method::QP, "method_qp"}, {"QEC", Method::QEC, "method_qec"}, {"L1", Method::L1, "method_l1"}};
  for (const auto& m : methods) {
    if (!canSwitch) ImGui::BeginDisabled();
    if (ImGui::RadioButton(m.label, state.method == m.method)) switchMethod(state, m.method);
    if (!canSwitch) ImGui::EndDisabled();
    if (!state.capabilities.methods && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
      ImGui::SetTooltip("%s", state.capabilities.why.c_str());
    markWidget(state, m.id);
    ImGui::SameLine();
  }
  ImGui::NewLine();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Re-optimizes all samples from the current (painted) targets.");
  ImGui::Checkbox("Heatmap", state.tool == Tool::Pose ? &state.heat.showInPose : &state.heat.show);
  markWidget(state, "heatmap");
  ImGui::SameLine();
  if (ImGui::RadioButton("Linear", !state.heat.log)) state.heat.log = false;
  ImGui::SameLine();
  if (ImGui::RadioButton("Log", state.heat.log)) state.heat.log = true;
  ImGui::SliderFloat("Opacity", &state.heat.opacity, 0.0f, 1.0f, "%.2f");
  if (state.activeControl >= 0) {
    ImGui::Text("Weights of control %ld", long(state.activeControl));
    colorBar(state);
  } else {
    ImGui::TextDisabled("Select a control point to see its weights.");
  }
}

}  // namespace kc::ui
