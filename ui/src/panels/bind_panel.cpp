#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "kc/app/pipeline.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/rebind.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

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

/// The "kernel-width" widget: Auto <label> (the value 0) with the width the next bind will use
/// beside it, or the width to set.
void kernelWidthWidget(AppState& state, const app::Backend& backend, const app::BackendParameter& parameter, double bindSpacing) {
  app::BindParams& p = state.bindParams;
  const double value = app::parameterValue(backend, parameter, p);
  bool automatic = value <= 0.0;
  const std::string label = "Auto " + parameter.label;
  if (checkbox(state, label.c_str(), &automatic,
               "Let kcwarp choose the smoothing width (sigma) from the sample spacing (recommended)."))
    app::setParameter(backend, parameter, p, automatic ? 0.0 : app::automaticSigma(p.spacing));
  ImGui::SameLine();
  const bool boundAuto = state.session && state.session->params.backend == p.backend &&
                         !(app::parameterValue(backend, parameter, state.session->params) > 0.0);
  const std::string boundSigma = automatic && boundAuto ? boundSigmaText(state) : "";
  if (!boundSigma.empty() && std::abs(bindSpacing - state.bound->spacing) < 1e-9) {
    // Bound with the automatic sigma at the spacing the next bind uses: the width it measured.
    ImGui::TextDisabled("%s", boundSigma.c_str());
    tooltip(
        "The width the bound weights use: 3T/pi with T the spacing measured on the samples (thesis eq. 3.28), "
        "smaller in proportion where the samples lie closer (narrow places). Bind measures it again.");
  } else if (automatic) {
    const auto [smallest, sigma] = plannedSigma(state);
    ImGui::TextDisabled("about %s", sigmaRangeText(sigma, smallest, sigma).c_str());
    tooltip(
        "Estimated as 3T/pi with T the spacing; Bind measures T on the actual samples (thesis eq. 3.28). "
        "Where the samples lie closer (narrow places), sigma is smaller in proportion.");
  } else {
    float sigma = static_cast<float>(value);
    ImGui::SetNextItemWidth(100);
    const std::string id = "##" + parameter.key;
    if (ImGui::DragFloat(id.c_str(), &sigma, 0.05f, 0.2f, 200.0f, "%.2f px"))
      app::setParameter(backend, parameter, p, std::max(0.2, double(sigma)));
    tooltip(parameter.tooltip.c_str());
  }
}

/// The "local-targets" widget: the switch, and while on, the locality length the bind will use
/// (pixels), which sets the backend's `locality` parameter (pixels) when dragged.
void localTargetsWidget(AppState& state, const app::Backend& backend, const app::BackendParameter& parameter) {
  app::BindParams& p = state.bindParams;
  bool on = app::parameterValue(backend, parameter, p) != 0.0;
  if (checkbox(state, parameter.label.c_str(), &on, parameter.tooltip.c_str()))
    app::setParameter(backend, parameter, p, on ? 1.0 : 0.0);
  if (!on) return;
  const auto pixels = std::find_if(backend.parameters().begin(), backend.parameters().end(),
                                   [](const app::BackendParameter& q) { return q.key == "locality"; });
  if (pixels == backend.parameters().end()) return;
  ImGui::SameLine();
  // In spacings (follows the spacing the bind will use, the default) or, once edited, in pixels.
  float locality = static_cast<float>(spacingPlan(state).locality);
  ImGui::SetNextItemWidth(100);
  if (ImGui::DragFloat("##locality", &locality, 0.5f, 1.0f, 2000.0f, "%.0f px"))
    app::setParameter(backend, *pixels, p, std::max(1.0, double(locality)));
  tooltip(pixels->tooltip.c_str());
}

/// A backend's described parameters (app::BackendParameter) drawn at `where`, one widget each
/// (a parameter's own widget, else its type's). `bindSpacing`: the spacing the next bind uses.
void parameterControls(AppState& state, const app::Backend& backend, app::BackendParameter::Panel where, double bindSpacing) {
  app::BindParams& p = state.bindParams;
  for (const app::BackendParameter& parameter : backend.parameters()) {
    if (parameter.panel != where || (parameter.shownWhen && !parameter.shownWhen(p))) continue;
    if (parameter.widget == "kernel-width") {
      kernelWidthWidget(state, backend, parameter, bindSpacing);
      continue;
    }
    if (parameter.widget == "local-targets") {
      localTargetsWidget(state, backend, parameter);
      continue;
    }
    const char* label = parameter.label.c_str();
    const double value = app::parameterValue(backend, parameter, p);
    double changed = value;
    switch (parameter.type) {
      case app::BackendParameter::Type::Boolean: {
        bool on = value != 0.0;
        if (ImGui::Checkbox(label, &on)) changed = on ? 1.0 : 0.0;
        break;
      }
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
        // An open upper end is kept out of reach of the slider.
        const double top = parameter.openMax ? std::nextafter(parameter.max, parameter.min) : parameter.max;
        if (!parameter.logarithmic) {
          float v = static_cast<float>(value);
          if (ImGui::SliderFloat(label, &v, static_cast<float>(parameter.min), static_cast<float>(top), "%.3g"))
            changed = std::clamp(double(v), parameter.min, top);
          break;
        }
        // A slider over log10 of the value, showing the value (ImGui's own logarithmic slider
        // squeezes ranges that start far below 1 against its left end); values snap to one digit.
        char shown[32];
        std::snprintf(shown, sizeof shown, "%.0e", value);
        float e = static_cast<float>(std::log10(value));
        if (ImGui::SliderFloat(label, &e, static_cast<float>(std::log10(parameter.min)), static_cast<float>(std::log10(top)),
                               shown)) {
          std::snprintf(shown, sizeof shown, "%.0e", std::pow(10.0, double(e)));
          changed = std::clamp(std::strtod(shown, nullptr), parameter.min, top);
        }
        break;
      }
    }
    labelled(state, label, parameter.tooltip.c_str());
    if (changed != value) app::setParameter(backend, parameter, p, changed);
  }
}

/// A backend's Advanced parameters under a collapsed header (nothing when it has none shown now).
void advancedControls(AppState& state, const app::Backend& backend, double bindSpacing) {
  const app::BindParams& p = state.bindParams;
  const auto& list = backend.parameters();
  if (std::none_of(list.begin(), list.end(), [&](const app::BackendParameter& q) {
        return q.panel == app::BackendParameter::Panel::Advanced && (!q.shownWhen || q.shownWhen(p));
      }))
    return;
  const bool open = ImGui::TreeNode("Advanced##bind");
  labelled(state, "Advanced", "Settings most pictures never need: their defaults are the recommended ones.");
  if (!open) return;
  parameterControls(state, backend, app::BackendParameter::Panel::Advanced, bindSpacing);
  ImGui::TreePop();
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
  } else if (idle && bindBehindPoses(state.undo)) {
    ImGui::SameLine();
    if (button(state, "Previous bind",
               "Back to the bind before this one, with its weights, in the present pose; "
               "Previous bind again comes back to this one."))
      showPreviousBind(state);
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
  if (const app::Backend* targets = backend.targetsBackend(p)) {
    char line[160];
    std::snprintf(line, sizeof line, " With %s initialization the %s mesh's edges are %.3g times this spacing.",
                  std::string(targets->displayName()).c_str(), std::string(targets->displayName()).c_str(),
                  backend.weightSpacing(p) / p.spacing);
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
  using Panel = app::BackendParameter::Panel;
  parameterControls(state, backend, Panel::Shown, bindSpacing);
  // The backend its targets come from (the kc backend's LBC initialization): that solver's parameters.
  if (const app::Backend* targets = backend.targetsBackend(p)) parameterControls(state, *targets, Panel::Shown, bindSpacing);
  advancedControls(state, backend, bindSpacing);
  ImGui::PopItemWidth();
  drawBoundSummary(state);
}

}  // namespace kc::ui
