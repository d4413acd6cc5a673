#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "kc/app/pipeline.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

struct Column {
  const char* name;
  const char* tip;
};

constexpr Column kColumns[] = {
    {"where", "Where the weights were checked. Hover a row's name for details."},
    {"|sum-1|", "How far the weights of a point are from adding up to exactly 1 (largest error). "
                "They must add up to 1, or the picture would shrink or grow by itself. Tiny is good."},
    {"repro px", "How far, in pixels, the weights put a point when nothing is moved (largest error). "
                 "Below 0.01 px is invisible."},
    {"min w", "The smallest weight found. Negative weights pull a part of the picture the opposite way "
              "of the point you drag."},
    {"neg", "How many checked places have a clearly negative weight (below -0.001)."},
};

/// An error measure in plain figures: "0" below rounding (1e-9), else one significant digit.
std::string errorText(double v) {
  if (std::abs(v) < 1e-9) return "0";
  char text[32];
  std::snprintf(text, sizeof text, "%.0e", v);
  return text;
}

void propertyRow(AppState& state, const char* name, const char* tip, const app::PropertyRow& r) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(name);
  labelled(state, name, tip);
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(errorText(r.partitionOfUnity).c_str());
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(errorText(r.reproduction).c_str());
  ImGui::TableNextColumn();
  ImGui::Text("%.3f", r.minWeight > -5e-4 ? std::max(r.minWeight, 0.0) : r.minWeight);  // no "-0.000"
  ImGui::TableNextColumn();
  ImGui::Text("%ld", long(r.negatives));
}

}  // namespace

void drawDiagnosticsPanel(AppState& state) {
  if (!state.bound) {
    ImGui::TextDisabled("Nothing bound yet.");
    return;
  }
  const bool can = state.session && !state.worker.busy();
  if (!can) ImGui::BeginDisabled();
  if (button(state, state.diagnostics ? "Refresh properties##diag" : "Measure properties##diag",
             "Check the weights of this bind: do they add up to 1, leave the picture in place when nothing moves, "
             "stay positive? Checked at the sample points, inside the cage and over the whole picture."))
    refreshDiagnostics(state);
  if (!can) ImGui::EndDisabled();
  if (state.diagnostics) {
    const app::Diagnostics& d = *state.diagnostics;
    if (ImGui::BeginTable("properties", 5, ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
      for (const Column& c : kColumns) ImGui::TableSetupColumn(c.name);
      ImGui::TableNextRow(ImGuiTableRowFlags_Headers);
      for (int k = 0; k < 5; ++k) {
        ImGui::TableSetColumnIndex(k);
        ImGui::TableHeader(kColumns[k].name);
        labelled(state, kColumns[k].name, kColumns[k].tip);
      }
      propertyRow(state, "samples", "At the sample points the weights were computed at.", d.samples);
      propertyRow(state, "inside", "At a grid of points inside the cage.", d.inside);
      if (d.outsideWeights) {
        propertyRow(state, "image", "At a grid of points over the whole picture, outside the cage too.", d.image);
      } else {
        // A field without weights outside the cage (LBC): nothing there to measure.
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted("outside");
        labelled(state, "outside",
                 ("No weights outside the cage: " + state.bound->capabilities.why +
                  ". The picture outside is kept or pinned (Outside the cage).")
                     .c_str());
        ImGui::TableNextColumn();
        ImGui::TextDisabled("none");
      }
      ImGui::EndTable();
    }
    ImGui::Text("Lagrange %s   edge linearity %s", errorText(d.lagrange).c_str(), errorText(d.edgeLinearity).c_str());
    labelled(state, "Lagrange", "Lagrange: how far each cage point's own weight is from 1 at that point. Edge linearity: "
                                "how far the weights along each cage edge are from a straight blend of its two points. "
                                "Small means the cage outline follows the points exactly.");
    if (d.drag.points > 0) {
      ImGui::Text("Drag area %.0f%% mean, %.0f%% max (point %ld)", 100.0 * d.drag.mean, 100.0 * d.drag.max, long(d.drag.maxControl));
      char tip[512];
      std::snprintf(tip, sizeof tip,
                    "How local the weights are: when you drag one cage point %.0f px, the part of the picture inside the cage that "
                    "moves by %.1f px or more (where that point's weight is at least %.4g, the tick on the heatmap's colour bar), "
                    "averaged over the points and for the point that moves the most. Smaller is more local. Checked every %d px; the "
                    "lowest weight there is %.3f (below 0 the picture moves against the drag).",
                    app::kDragPixels, app::kVisibleShift, app::kDragWeight, d.drag.step, d.drag.minWeight);
      labelled(state, "Drag area", tip);
    }
    ImGui::TextDisabled("grid step %d px, %.0f ms", d.pixelStep, d.evalSeconds * 1e3);
    labelled(state, "grid step", "Spacing of the check grid, in pixels, and how long the check took.");
  }
  ImGui::Separator();
  // Solver outcomes of the bind (and of the last method switch): warning colour when something fell back.
  // Plain words here; the solvers' own report is the tooltip.
  const std::vector<std::string> problems = state.bound->report.problems();
  if (problems.empty()) ImGui::TextWrapped("Solver: every weight was computed as asked.");
  else ImGui::TextUnformatted("Solver warnings:");
  const std::string solverTip =
      "What the solvers of the last bind or method switch reported. A warning means some sample "
      "points got fallback weights: usually harmless, shown so nothing is hidden. Details: " +
      state.bound->report.summary() + (state.rigidityDetails.empty() ? "" : "; " + state.rigidityDetails);
  labelled(state, "Solver", solverTip.c_str());
  for (const std::string& p : problems) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.75f, 0.2f, 1.0f));
    ImGui::TextWrapped("%s", p.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::Separator();
  const DeformReport& r = state.deformReport;
  if (r.flippedTriangles > 0)
    ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.45f, 1.0f), "Flipped triangles: %ld (%.0f px^2)", long(r.flippedTriangles), r.flippedArea);
  else
    ImGui::Text("Flipped triangles: 0");
  labelled(state, "Flipped triangles", "Places where the pose folds the picture over itself (shown in red on the "
                                       "picture when View > Fold-overs is on), and their area before the pose.");
  if (r.harmonicFolds > 0) {
    ImGui::Text("Background untangled: %ld of %ld folds", long(r.harmonicFolds - r.repairedFolds), long(r.harmonicFolds));
    labelled(state, "Background untangled", "The pose squeezes the background next to the cage so much that it would "
                                            "fold; kcwarp moves the background points there so it does not. Folds "
                                            "left over happen where the cage is pushed past the picture's border.");
  }
  ImGui::Text("Size change: %.2g to %.2g times", r.minJacobian, r.maxJacobian);
  labelled(state, "Size change", "How much the pose grows or shrinks each small piece of the picture, smallest and largest: "
                                 "1 = same size, 2 = twice the area, below 0 = folded over (the determinant of the "
                                 "warp's Jacobian, det J).");
  ImGui::Text("Mesh: %ld vertices, %zu triangles (%.1f px)", long(state.mesh.restVertices().rows()), state.mesh.triangles().size(),
              state.mesh.options().spacing);
  labelled(state, "Mesh", "The picture is drawn as a grid of small triangles that follow the pose; the grid spacing in pixels.");
  if (state.bound->report.meshVertices() > 0) {
    ImGui::Text("Mesh: %ld vertices, controls: %ld", long(state.bound->report.meshVertices()), long(state.bound->cage.size()));
    labelled(state, "LBC mesh", "Vertices of the triangle mesh of the cage's inside that LBC computed the weights at, "
                                "and the number of cage points.");
  } else {
    ImGui::Text("Samples: %ld, controls: %ld", long(state.bound->samples.size()), long(state.bound->cage.size()));
    labelled(state, "Samples", "Sample points the weights were computed at, and the number of cage points.");
  }
  if (const LobeLiftReport& lift = state.bound->report.lift; lift.lobes > 0 || lift.deepestBefore != 0.0) {
    if (lift.lobes > 0)
      ImGui::TextWrapped("Lobes lifted: %ld (lowest %.3f -> %.3f)", long(lift.lobes), lift.deepestBefore, lift.deepestAfter);
    else ImGui::TextWrapped("Lobes lifted: none (lowest %.3f)", lift.deepestBefore);
    labelled(state, "Lobes lifted",
             "With Lift lobes on (Bind > Advanced): places inside the cage where a point's weight dipped "
             "below 0, so that dragging the point would move them slightly the wrong way, raised "
             "after the bind; and the lowest weight found there before and after the lift. Dips right beside "
             "another cage point are left as they are.");
  }
  ImGui::Separator();
  const Timings& t = state.timings;
  ImGui::Text("Bind: %.2f s", t.bindSeconds);
  labelled(state, "Bind:", "How long the last Bind took.");
  ImGui::Text("Re-optimization: %.1f ms (%ld samples)", t.reoptimizeMs, long(t.reoptimizeSamples));
  labelled(state, "Re-optimization", "How long the weights took to update after the last brush stroke or method switch, "
                                     "and at how many sample points.");
  ImGui::Text("Mesh weights: %.1f ms", t.meshWeightsMs);
  labelled(state, "Mesh weights", "How long updating the weights at the drawing grid took.");
  ImGui::Text("Release -> picture: %.0f ms", t.releaseToPictureMs);
  labelled(state, "Release -> picture", "From letting go of the brush to the updated picture.");
  ImGui::Text("Frame: %.1f ms (deform %.2f ms)", t.frameMs, t.deformMs);
  labelled(state, "Frame", "Time to draw one frame of the window, and the part spent moving the picture to the pose.");
}

}  // namespace kc::ui
