#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "kc/app/pipeline.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"

namespace kc::ui {
namespace {

/// A combo over an enum's values with app::toString labels; returns true on change.
template <class E, std::size_t N>
bool enumCombo(const char* label, E& value, const E (&values)[N]) {
  bool changed = false;
  if (ImGui::BeginCombo(label, std::string(app::toString(value)).c_str())) {
    for (E v : values) {
      if (ImGui::Selectable(std::string(app::toString(v)).c_str(), v == value)) {
        value = v;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

}  // namespace

void drawBindPanel(AppState& state) {
  app::BindParams& p = state.bindParams;
  ImGui::PushItemWidth(150);
  float spacing = static_cast<float>(p.spacing);
  if (ImGui::SliderFloat("Spacing h", &spacing, 2.0f, 40.0f, "%.1f px", ImGuiSliderFlags_Logarithmic)) p.spacing = spacing;
  bool autoSigma = p.kc.sigma <= 0.0;
  if (ImGui::Checkbox("Auto sigma", &autoSigma)) p.kc.sigma = autoSigma ? 0.0 : app::automaticSigma(p.spacing);
  ImGui::SameLine();
  if (autoSigma) {
    ImGui::TextDisabled("~ %.2f px (3T/pi, T measured)", app::automaticSigma(p.spacing));
  } else {
    float sigma = static_cast<float>(p.kc.sigma);
    ImGui::SetNextItemWidth(100);
    if (ImGui::DragFloat("##sigma", &sigma, 0.05f, 0.2f, 200.0f, "%.2f px")) p.kc.sigma = std::max(0.2f, sigma);
  }
  static constexpr InitMethod inits[] = {InitMethod::HeatLinear, InitMethod::HeatImpulse, InitMethod::InverseDistance};
  static constexpr Method methods[] = {Method::QP, Method::QEC, Method::L1};
  static constexpr InterpMode interps[] = {InterpMode::Exact, InterpMode::Thesis};
  enumCombo("Initialization", p.kc.init.method, inits);
  if (p.kc.init.method == InitMethod::HeatLinear) {
    // Screened targets (opt-in): how far a control point's influence reaches inside the shape.
    bool screened = p.kc.init.locality != 0.0;
    if (ImGui::Checkbox("Local targets", &screened)) p.kc.init.locality = screened ? -1.0 : 0.0;
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Screened heat diffusion: targets decay with the distance inside the shape.\n"
                        "More local, but the QP may then give far controls small weights.\n"
                        "Off: smooth, global (harmonic-like) targets. Takes effect at the next Bind.");
    if (screened) {
      ImGui::SameLine();
      float locality = static_cast<float>(p.kc.init.locality < 0.0 ? automaticLocality(state.cage.C) : p.kc.init.locality);
      ImGui::SetNextItemWidth(100);
      if (ImGui::DragFloat("##locality", &locality, 0.5f, 1.0f, 2000.0f, "%.0f px")) p.kc.init.locality = std::max(1.0f, locality);
    }
  }
  enumCombo("Method", p.kc.method, methods);
  enumCombo("Interpolation", p.kc.interp, interps);
  ImGui::PopItemWidth();

  if (!state.cageStatus.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, state.cage.closed ? ImVec4(1.0f, 0.42f, 0.42f, 1.0f) : ImVec4(0.75f, 0.85f, 1.0f, 1.0f));
    ImGui::TextWrapped("%s", state.cageStatus.c_str());
    ImGui::PopStyleColor();
  } else {
    ImGui::TextDisabled("Cage: %ld points, valid.", long(state.cage.size()));
  }
  const bool canBind = state.cageValid && !state.worker.busy() && !state.source.empty();
  if (!canBind) ImGui::BeginDisabled();
  // "##run": the side panel's "Bind" header has the label "Bind" too; one ID would take both clicks.
  if (ImGui::Button("Bind##run", ImVec2(120, 0))) startBind(state);
  if (!canBind) ImGui::EndDisabled();
  markWidget(state, "bind");
  if (state.bound && !(state.cage.C.rows() == state.boundCage.C.rows() && state.cage.C == state.boundCage.C)) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "cage edited: Bind to apply");
  }
  if (ImGui::Button("Load cage...")) requestPath(state, PathPurpose::LoadCage, "");
  ImGui::SameLine();
  if (ImGui::Button("Save cage...")) requestPath(state, PathPurpose::SaveCage, "cage.json");
}

}  // namespace kc::ui
