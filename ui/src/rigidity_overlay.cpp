// The rigid regions over the canvas (canvas.h, drawRigidityOverlay): the per-sample rigidity ρ as a
// cyan tint carried by the display mesh (so it follows the warp), and the rigid polygons of a
// structure file or session outlined, deformed with the pose.
#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "kc/core/spatial_grid.h"
#include "kc/ui/canvas.h"
#include "kc/ui/rigidity_edits.h"
#include "overlay_draw.h"

namespace kc::ui {
namespace {

using overlay::im;
using overlay::rgba;

/// The tint's colour (the cyan of `warp --overlay`'s rigid outlines) and its opacity at ρ = 1.
constexpr int kTint[3] = {0, 200, 220};
constexpr double kTintAlpha = 150.0;

/// ρ as the canvas shows it: the stroke being painted, else the session's.
const std::vector<double>& shownRigidity(const AppState& state) {
  return state.rigidTool.active() ? state.rigidTool.stroke() : boundRigidity(state);
}

/// ρ at the display mesh's rest vertices: a smooth average of the samples' ρ within R = 1.5 h,
/// ρ(v) = Σ_s ρ_s φ_s / Σ_s φ_s with φ_s = (1 − (|v − x_s| / R)²)² (every sample counts, so the
/// tint fades out where the painted samples end); empty when nothing is rigid.
std::vector<float> vertexRigidity(const AppState& state) {
  std::vector<float> tint;
  const std::vector<double>& rho = shownRigidity(state);
  const Points& X = state.bound->samples.X;
  if (!anyRigid(rho) || rho.size() != static_cast<std::size_t>(X.rows())) return tint;
  const Points& V = state.mesh.restVertices();
  const double R = 1.5 * (state.bound->spacing > 0.0 ? state.bound->spacing : 6.0);
  // Vertices with no rigid sample within R stay 0 (the test is a query of the few rigid samples).
  std::vector<Index> rigid;
  for (Index s = 0; s < X.rows(); ++s)
    if (rho[static_cast<std::size_t>(s)] > 0.0) rigid.push_back(s);
  const SpatialGrid rigidGrid(X(rigid, Eigen::all), R), allGrid(X, R);
  tint.assign(static_cast<std::size_t>(V.rows()), 0.0f);
  for (Index v = 0; v < V.rows(); ++v) {
    const Vec2 p = V.row(v).transpose();
    bool near = false;
    rigidGrid.forEachWithin(p, R, [&](Index, double) { near = true; });
    if (!near) continue;
    double num = 0.0, den = 0.0;
    allGrid.forEachWithin(p, R, [&](Index s, double d2) {
      const double q = 1.0 - d2 / (R * R);
      num += q * q * rho[static_cast<std::size_t>(s)];
      den += q * q;
    });
    if (den > 0.0) tint[static_cast<std::size_t>(v)] = static_cast<float>(num / den);
  }
  return tint;
}

/// The tint: the display mesh's triangles where ρ > 0, each vertex's opacity ∝ its ρ.
void drawTint(AppState& state, ImDrawList* dl) {
  // Recomputed when the mesh or the ρ shown changes.
  const std::vector<float>& r =
      state.rigidTint.get({state.meshVersion, state.rigidityVersion}, [&] { return vertexRigidity(state); });
  const Points& rest = state.mesh.restVertices();
  if (r.empty() || static_cast<Index>(r.size()) != rest.rows()) return;
  const bool warped = showsWarp(state) && state.mesh.deformedVertices().rows() == rest.rows();
  const Points& P = warped ? state.mesh.deformedVertices() : rest;
  const ImVec2 uv = ImGui::GetFontTexUvWhitePixel();
  for (const auto& t : state.mesh.triangles()) {
    if (std::max({r[static_cast<std::size_t>(t[0])], r[static_cast<std::size_t>(t[1])], r[static_cast<std::size_t>(t[2])]}) < 0.01f) continue;
    dl->PrimReserve(3, 3);
    for (int k = 0; k < 3; ++k) {
      const int a = static_cast<int>(std::lround(kTintAlpha * std::clamp(r[static_cast<std::size_t>(t[k])], 0.0f, 1.0f)));
      dl->PrimVtx(im(state.view.toScreen(P.row(t[k]).transpose())), uv, rgba(kTint[0], kTint[1], kTint[2], a));
    }
  }
}

/// The rigid polygons' outlines, through their points moved by the field.
void drawOutlines(const AppState& state, ImDrawList* dl) {
  const bool rest =
      !showsWarp(state) || isRestPose(state.pose) || state.pose.size() != static_cast<std::size_t>(state.bound->cage.size());
  for (const BoundLine& o : state.bound->rigidOutlines) {
    if (o.W.cols() != state.bound->cage.size()) continue;
    const Points P = rest ? o.X : deformPoints(o.W, o.X, state.bound->cage.C, state.pose);
    std::vector<ImVec2> s;
    for (Index i = 0; i < P.rows(); ++i) s.push_back(im(state.view.toScreen(P.row(i).transpose())));
    const int n = static_cast<int>(s.size());
    dl->AddPolyline(s.data(), n, rgba(20, 20, 28, 200), 0, 4.0f);
    dl->AddPolyline(s.data(), n, rgba(kTint[0], kTint[1], kTint[2]), 0, 2.0f);
  }
}

}  // namespace

void drawRigidityOverlay(AppState& state) {
  if (state.source.empty() || !state.bound || state.showOriginal) return;
  if (state.tool != Tool::Rigid && !state.show.rigid) return;
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  dl->PushClipRect(im(state.view.canvasMin), im(state.view.canvasMin + state.view.canvasSize), true);
  drawTint(state, dl);
  drawOutlines(state, dl);
  dl->PopClipRect();
}

}  // namespace kc::ui
