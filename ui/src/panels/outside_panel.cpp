// The outside-the-cage choice: what happens to the picture around the cage, in the view and the export.
#include <imgui.h>

#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {

void drawOutsidePanel(AppState& state) {
  const struct {
    OutsideMode mode;
    const char* label;
    const char* tip;
    const char* id;  // UI automation name of the entry
  } modes[] = {
      {OutsideMode::Pinned, "Pinned border",
       "The edges of the picture stay where they are; the background between the cage and the "
       "edges stretches smoothly to follow what you move. Good for a figure on a background.", "outside_pinned"},
      {OutsideMode::Deform, "Move everything",
       "The whole picture follows the control points, also far outside the cage "
       "(the original kernel coordinates). Horizons and picture corners may move.", "outside_deform"},
      {OutsideMode::Fixed, "Keep outside",
       "Only the inside of the cage moves; it is drawn over the untouched picture, "
       "so the old outline may show behind it.", "outside_fixed"},
      {OutsideMode::Transparent, "Cut out",
       "Only the inside of the cage is drawn; everything else is transparent in the view "
       "and in the exported PNG.", "outside_transparent"},
  };
  int current = 0;
  for (int k = 0; k < 4; ++k)
    if (modes[k].mode == state.outside) current = k;
  const app::BackendCapabilities caps = shownCapabilities(state);
  const bool busy = state.worker.busy();
  if (busy) ImGui::BeginDisabled();
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.6f);
  const bool open = ImGui::BeginCombo("Outside the cage", modes[current].label);
  markWidget(state, "outside_mode");
  if (!open && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) showTooltip(modes[current].tip);
  if (open) {
    for (int k = 0; k < 4; ++k) {
      // A session (or, before a bind, a backend) without weights outside the cage (LBC) cannot
      // move the whole picture.
      // A session sampled only in a band around the cage offers it through a new bind.
      const bool unavailable = modes[k].mode == OutsideMode::Deform && !caps.outsideCage && !bandNeedsFrameBind(state);
      const ImGuiSelectableFlags flags = unavailable ? ImGuiSelectableFlags_Disabled : 0;
      if (ImGui::Selectable(modes[k].label, k == current, flags) && k != current) setOutsideMode(state, modes[k].mode);
      markWidget(state, modes[k].id);
      if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        showTooltip(unavailable ? caps.why.c_str() : modes[k].tip);
    }
    ImGui::EndCombo();
  }
  if (busy) ImGui::EndDisabled();
}

}  // namespace kc::ui
