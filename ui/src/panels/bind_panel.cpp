#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "kc/app/pipeline.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

/// A combo over an enum's values with app::toString labels; returns true on change.
template <class E, std::size_t N>
bool enumCombo(const char* label, E& value, const E (&values)[N], const char* tip) {
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
  tooltip(tip);
  return changed;
}

/// The backend switch: one radio button per backend (app::backendNames) for the next Bind.
void backendSwitch(AppState& state) {
  app::BindParams& p = state.bindParams;
  ImGui::TextUnformatted("Weights");
  tooltip("Which method computes the influence of each cage point at the next Bind.");
  for (const std::string_view name : app::backendNames()) {
    const app::Backend& backend = app::backendFor(name);
    ImGui::SameLine();
    const std::string label = std::string(backend.displayName()) + "##backend";
    if (radio(state, label.c_str(), p.backend == name, std::string(backend.tooltip()).c_str())) p.backend = std::string(name);
  }
}

/// "2.1-11.3 px" for a graded spacing (the smallest and the largest), "11.3 px" for one spacing.
/// (An ASCII hyphen: the GUI's font has Latin-1 glyphs only.)
std::string spacingRange(double smallest, double largest) {
  char text[64];
  if (smallest < largest - 0.05) std::snprintf(text, sizeof text, "%.1f-%.1f px", smallest, largest);
  else std::snprintf(text, sizeof text, "%.1f px", largest);
  return text;
}

/// The Auto spacing tooltip, with the budget the automatic spacing keeps to.
std::string autoSpacingTip(bool mesh) {
  char text[400];
  if (mesh)
    std::snprintf(text, sizeof text,
                  "Let kcwarp choose the mesh's edge length: 6 px, longer on big cages so that Bind takes seconds, not "
                  "minutes (about %.0f mesh points inside the cage), shorter near narrow places. Untick to set it yourself.",
                  app::kAutoLbcVertices);
  else
    std::snprintf(text, sizeof text,
                  "Let kcwarp choose the sample spacing: 6 px, wider on big pictures so that Bind takes seconds, not minutes "
                  "(about %.0f samples over the cage and a band around it), finer near narrow places. Untick to set it yourself.",
                  app::kAutoSpacingSamples);
  return text;
}

/// The tooltip of the spacing the next bind uses: its range and its sample (or mesh point) count.
std::string plannedSpacingTip(const Document::ShownSpacing& plan, bool mesh) {
  char text[400];
  const char* points = mesh ? "mesh points" : "samples";
  if (plan.minSpacing < plan.spacing - 0.05)
    std::snprintf(text, sizeof text,
                  "What Bind will use for this picture and cage: %.1f px apart away from narrow places, closer where the "
                  "cage is narrow, down to %.1f px at its narrowest place; about %.0f %s%s.",
                  plan.spacing, plan.minSpacing, plan.points, points, mesh ? " (a few more near narrow places)" : "");
  else
    std::snprintf(text, sizeof text, "What Bind will use for this picture and cage: %.1f px apart everywhere; about %.0f %s.",
                  plan.spacing, plan.points, points);
  return text;
}

/// A backend's described parameters (app::BackendParameter), one widget each.
void parameterControls(AppState& state, const app::Backend& backend) {
  app::BindParams& p = state.bindParams;
  for (const app::BackendParameter& parameter : backend.parameters()) {
    const char* label = parameter.label.c_str();
    const double value = app::parameterValue(backend, parameter, p);
    double changed = value;
    switch (parameter.type) {
      case app::BackendParameter::Type::Choice:
        if (ImGui::BeginCombo(label, app::parameterText(parameter, value).c_str())) {
          for (std::size_t k = 0; k < parameter.choices.size(); ++k)
            if (ImGui::Selectable(parameter.choices[k].c_str(), double(k) == value)) changed = double(k);
          ImGui::EndCombo();
        }
        break;
      case app::BackendParameter::Type::Integer: {
        int v = static_cast<int>(value);
        const int step =
            static_cast<int>(std::max(1.0, std::pow(10.0, std::floor(std::log10(std::max(1.0, parameter.max))) - 5)));
        if (ImGui::InputInt(label, &v, step, 10 * step)) changed = std::clamp(double(v), parameter.min, parameter.max);
        break;
      }
      case app::BackendParameter::Type::Number: {
        if (!parameter.logarithmic) {
          float v = static_cast<float>(value);
          if (ImGui::SliderFloat(label, &v, static_cast<float>(parameter.min), static_cast<float>(parameter.max), "%.3g"))
            changed = std::clamp(double(v), parameter.min, parameter.max);
          break;
        }
        // A slider over log10 of the value, showing the value (ImGui's own logarithmic slider
        // squeezes ranges that start far below 1 against its left end); values snap to one digit.
        char shown[32];
        std::snprintf(shown, sizeof shown, "%.0e", value);
        float e = static_cast<float>(std::log10(value));
        if (ImGui::SliderFloat(label, &e, static_cast<float>(std::log10(parameter.min)),
                               static_cast<float>(std::log10(parameter.max)), shown)) {
          std::snprintf(shown, sizeof shown, "%.0e", std::pow(10.0, double(e)));
          changed = std::clamp(std::strtod(shown, nullptr), parameter.min, parameter.max);
        }
        break;
      }
    }
    labelled(state, label, parameter.tooltip.c_str());
    if (changed != value) app::setParameter(backend, parameter, p, changed);
  }
}

/// The cage's status and the Bind row (Previous / Next bind, the cage-edited hint): above the
/// parameters, so that Bind stays in one place whichever backend's parameters are shown.
void drawBindButtons(AppState& state) {
  if (!state.cageStatus.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, cageComplete(state.cage) ? ImVec4(1.0f, 0.42f, 0.42f, 1.0f) : ImVec4(0.75f, 0.85f, 1.0f, 1.0f));
    ImGui::TextWrapped("%s", state.cageStatus.c_str());
    ImGui::PopStyleColor();
    if (cageComplete(state.cage)) ImGui::TextDisabled("Point numbers are shown on the picture (Cage tool).");
  } else {
    ImGui::TextDisabled("Cage: %ld points, valid.", long(state.cage.size()));
  }
  const bool canBind = state.cageValid && !state.worker.busy() && !state.source.empty();
  if (!canBind) ImGui::BeginDisabled();
  // "##run": the side panel's "Bind" header has the label "Bind" too; one ID would take both clicks.
  if (button(state, "Bind##run",
             "Compute how each cage point pulls on the picture (Ctrl+B). Then drag points with the Pose tool.",
             ImVec2(120, 0)))
    requestBind(state);
  if (!canBind) ImGui::EndDisabled();
  // The bind before the last one (another backend, say) one click away, and back: undo and redo of
  // the bind while nothing was done since.
  const UndoEntry* previous = state.undo.nextUndo();
  const UndoEntry* next = state.undo.nextRedo();
  const bool idle = state.session && !state.worker.busy();
  if (idle && previous && std::holds_alternative<BindEdit>(previous->edit)) {
    ImGui::SameLine();
    if (button(state, "Previous bind", "Back to the bind before this one, with its weights and pose (Ctrl+Z); "
                                       "Next bind then comes back to this one."))
      undo(state);
  } else if (idle && next && std::holds_alternative<BindEdit>(next->edit)) {
    ImGui::SameLine();
    if (button(state, "Next bind", "Forward to the bind you came back from (Ctrl+Shift+Z).")) redo(state);
  }
  if (state.bound && !(state.cage.C.rows() == state.bound->cage.C.rows() && state.cage.C == state.bound->cage.C)) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "cage edited: Bind to apply");
  }
}

/// What the bound session was computed with; Load / Save cage.
void drawBoundSummary(AppState& state) {
  if (state.bound) {  // what the bound session was computed with
    const bool mesh = state.bound->report.meshVertices() > 0;
    const std::string sigma = boundSigmaText(state);
    // Wrapped at the panel's edge: with a graded sigma the line is longer than the panel is wide.
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("Bound: spacing %s,%s%s %ld %s", spacingRange(state.bound->minSpacing, state.bound->spacing).c_str(),
                       sigma.empty() ? "" : " sigma ", sigma.empty() ? "" : (sigma + ",").c_str(),
                       long(mesh ? state.bound->report.meshVertices() : state.bound->samples.size()),
                       mesh ? "mesh points" : "samples");
    ImGui::PopStyleColor();
    tooltip("The spacing the weights of the bound picture were computed at (closer where the cage is narrow), their "
            "smoothing width sigma (smaller in proportion where the spacing is) and how many points they were computed "
            "at. Show the points with View > Samples.");
  }
  if (button(state, "Load cage...", "Read a cage outline from a JSON file (it is bound right away).")) requestPath(state, PathPurpose::LoadCage, "");
  ImGui::SameLine();
  if (button(state, "Save cage...", "Write the cage outline to a JSON file.")) requestPath(state, PathPurpose::SaveCage, "cage.json");
}

}  // namespace

void drawBindPanel(AppState& state) {
  app::BindParams& p = state.bindParams;
  drawBindButtons(state);
  backendSwitch(state);
  const app::Backend& backend = app::backendFor(p.backend);
  const bool mesh = !backend.capabilities().outsideCage;  // the weights live on a mesh of the cage's inside
  ImGui::PushItemWidth(150);
  checkbox(state, "Auto spacing", &state.autoSpacing, autoSpacingTip(mesh).c_str());
  const bool planned = !state.source.empty() && state.cageValid;
  if (state.autoSpacing && planned) {
    const Document::ShownSpacing& plan = spacingPlan(state);
    ImGui::SameLine();
    ImGui::TextDisabled("%s", spacingRange(plan.minSpacing, plan.spacing).c_str());
    tooltip(plannedSpacingTip(plan, mesh).c_str());
  }
  // What the next bind uses: the automatic spacing under Auto spacing, else the slider's.
  const double bindSpacing = state.autoSpacing && planned ? spacingPlan(state).spacing : p.spacing;
  ImGui::BeginDisabled(state.autoSpacing);
  // Greyed under Auto spacing, the slider shows the spacing the bind will use, not the last one set.
  float spacing = static_cast<float>(bindSpacing);
  if (ImGui::SliderFloat("Spacing h", &spacing, 2.0f, 40.0f, "%.1f px", ImGuiSliderFlags_Logarithmic)) p.spacing = spacing;
  ImGui::EndDisabled();
  std::string tip = state.autoSpacing ? "Chosen automatically (Auto spacing); untick Auto spacing to set it."
                    : mesh ? "Edge length of the triangle mesh of the cage's inside away from narrow places, in pixels. "
                             "Smaller: finer detail, slower Bind. Larger: faster, coarser."
                           : "Distance between the sample points the weights are computed at, away from narrow places, in "
                             "pixels. Smaller: finer detail, slower Bind. Larger: faster, smoother.";
  if (!mesh && p.kc.init.method == InitMethod::Lbc) {
    char line[128];
    std::snprintf(line, sizeof line, " With LBC initialization the LBC mesh's edges are %.3g times this spacing.",
                  1.0 / app::kLbcTargetSampling);
    tip += line;
  }
  tooltip(tip.c_str());
  if (!state.autoSpacing && planned) {
    // A graded bind samples narrow places more finely than the slider says.
    const Document::ShownSpacing& plan = spacingPlan(state);
    if (plan.minSpacing < plan.spacing - 0.05) {
      ImGui::TextDisabled("Used: %s", spacingRange(plan.minSpacing, plan.spacing).c_str());
      tooltip(plannedSpacingTip(plan, mesh).c_str());
    }
  }
  if (!backend.capabilities().targets) {  // the kc backend's parameters below
    parameterControls(state, backend);
    ImGui::PopItemWidth();
    drawBoundSummary(state);
    return;
  }
  bool autoSigma = p.kc.sigma <= 0.0;
  if (checkbox(state, "Auto sigma", &autoSigma,
               "Let kcwarp choose the smoothing width (sigma) from the sample spacing (recommended)."))
    p.kc.sigma = autoSigma ? 0.0 : app::automaticSigma(p.spacing);
  ImGui::SameLine();
  const bool boundAuto = state.session && !(state.session->params.kc.sigma > 0.0);
  const std::string boundSigma = autoSigma && boundAuto ? boundSigmaText(state) : "";
  if (!boundSigma.empty() && std::abs(bindSpacing - state.bound->spacing) < 1e-9) {
    // Bound with the automatic sigma at the spacing the next bind uses: the width it measured.
    ImGui::TextDisabled("%s", boundSigma.c_str());
    tooltip("The width the bound weights use: 3T/pi with T the spacing measured on the samples (thesis eq. 3.28), "
            "smaller in proportion where the samples lie closer (narrow places). Bind measures it again.");
  } else if (autoSigma) {
    const auto [smallest, sigma] = plannedSigma(state);
    ImGui::TextDisabled("about %s", sigmaRangeText(sigma, smallest, sigma).c_str());
    tooltip("Estimated as 3T/pi with T the spacing; Bind measures T on the actual samples (thesis eq. 3.28). "
            "Where the samples lie closer (narrow places), sigma is smaller in proportion.");
  } else {
    float sigma = static_cast<float>(p.kc.sigma);
    ImGui::SetNextItemWidth(100);
    if (ImGui::DragFloat("##sigma", &sigma, 0.05f, 0.2f, 200.0f, "%.2f px")) p.kc.sigma = std::max(0.2f, sigma);
    tooltip("Smoothing width in pixels: larger gives smoother but less exact weights.");
  }
  static constexpr InitMethod inits[] = {InitMethod::HeatLinear, InitMethod::HeatImpulse, InitMethod::InverseDistance,
                                         InitMethod::Lbc};
  static constexpr InterpMode interps[] = {InterpMode::Exact, InterpMode::Thesis};
  enumCombo("Initialization", p.kc.init.method, inits,
            "How the starting influences are guessed before they are optimized:\n"
            "heat-linear: heat spread from the cage outline, linear along its edges (recommended);\n"
            "heat-impulse: heat spread from the points only;\n"
            "inverse-distance: nearer points pull harder;\n"
            "lbc: the local influences of LBC inside the cage (as local as LBC, still paintable; slower Bind).");
  markWidget(state, "Initialization");
  if (const app::Backend* targets = backend.targetsBackend(p)) parameterControls(state, *targets);  // its solver's parameters
  if (p.kc.init.method == InitMethod::HeatLinear) {
    // Screened targets (the default, 1.5 spacings): how far a control point's influence reaches inside the shape.
    bool screened = p.kc.locality.rule != app::Locality::Rule::Off;
    if (checkbox(state, "Local targets", &screened,
                 "A point pulls mostly on the parts of the shape near it (screened heat diffusion, its faint far tail "
                 "dropped), about as locally as LBC (recommended). Off: smooth influences that reach further. Takes effect "
                 "at the next Bind.")) {
      p.kc.locality = screened ? app::Locality{} : app::Locality{app::Locality::Rule::Off, 0.0};
      p.kc.targetFloor = screened ? app::kTargetFloor : 0.0;
    }
    if (screened) {
      ImGui::SameLine();
      // In spacings (follows the spacing the bind will use, the default) or, once edited, in pixels.
      float locality = static_cast<float>(spacingPlan(state).locality);
      ImGui::SetNextItemWidth(100);
      if (ImGui::DragFloat("##locality", &locality, 0.5f, 1.0f, 2000.0f, "%.0f px"))
        p.kc.locality = {app::Locality::Rule::Pixels, std::max(1.0f, locality)};
      tooltip("How far (pixels, inside the shape) a point's pull reaches; by default 1.5 sample spacings, more in a deep shape "
              "with few points.");
    }
  }
  enumCombo("Interpolation", p.kc.interp, interps,
            "exact: influences add up to exactly 1 everywhere, so unmoved parts stay put (recommended);\n"
            "thesis: the plain kernel form of the thesis (about 0.1% off).");
  ImGui::PopItemWidth();
  drawBoundSummary(state);
}

}  // namespace kc::ui
