#include <imgui.h>

#include <string>
#include <vector>

#include "kc/app/pipeline.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"

namespace kc::ui {
namespace {

void propertyRow(const char* name, const app::PropertyRow& r) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(name);
  ImGui::TableNextColumn();
  ImGui::Text("%.1e", r.partitionOfUnity);
  ImGui::TableNextColumn();
  ImGui::Text("%.1e", r.reproduction);
  ImGui::TableNextColumn();
  ImGui::Text("%.3f", r.minWeight);
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
  if (ImGui::Button(state.diagnostics ? "Refresh properties" : "Measure properties")) refreshDiagnostics(state);
  if (!can) ImGui::EndDisabled();
  if (state.diagnostics) {
    const app::Diagnostics& d = *state.diagnostics;
    if (ImGui::BeginTable("properties", 5, ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
      ImGui::TableSetupColumn("where");
      ImGui::TableSetupColumn("|sum-1|");
      ImGui::TableSetupColumn("repro px");
      ImGui::TableSetupColumn("min w");
      ImGui::TableSetupColumn("neg");
      ImGui::TableHeadersRow();
      propertyRow("samples", d.samples);
      propertyRow("inside", d.inside);
      propertyRow("image", d.image);
      ImGui::EndTable();
    }
    ImGui::Text("Lagrange %.1e   edge linearity %.1e", d.lagrange, d.edgeLinearity);
    ImGui::TextDisabled("grid step %d px, %.0f ms", d.pixelStep, d.evalSeconds * 1e3);
  }
  ImGui::Separator();
  // Solver outcomes of the bind (and of the last method switch): warning colour when something fell back.
  const std::vector<std::string> problems = state.reports.problems();
  if (problems.empty()) ImGui::TextWrapped("%s", state.reports.summary().c_str());
  else ImGui::TextUnformatted("Solver warnings:");
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
  ImGui::Text("det J in [%.3g, %.3g]", r.minJacobian, r.maxJacobian);
  ImGui::Text("Mesh: %ld vertices, %zu triangles (%.1f px)", long(state.mesh.restVertices().rows()), state.mesh.triangles().size(),
              state.mesh.options().spacing);
  ImGui::Text("Samples: %ld, controls: %ld", long(state.samples.size()), long(state.boundCage.size()));
  ImGui::Separator();
  const Timings& t = state.timings;
  ImGui::Text("Bind: %.2f s", t.bindSeconds);
  ImGui::Text("Re-optimization: %.1f ms (%ld samples)", t.reoptimizeMs, long(t.reoptimizeSamples));
  ImGui::Text("Mesh weights: %.1f ms", t.meshWeightsMs);
  ImGui::Text("Release -> picture: %.0f ms", t.releaseToPictureMs);
  ImGui::Text("Frame: %.1f ms (deform %.2f ms)", t.frameMs, t.deformMs);
}

}  // namespace kc::ui
