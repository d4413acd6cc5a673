// Overlays of the canvas (canvas.h): drawn in screen space on ImGui's background draw list, so
// they sit above the GL picture and below the panels.
#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "kc/app/heatmap.h"
#include "kc/ui/canvas.h"

namespace kc::ui {
namespace {

ImVec2 im(const Vec2& v) { return {static_cast<float>(v.x()), static_cast<float>(v.y())}; }
ImU32 rgba(int r, int g, int b, int a = 255) { return IM_COL32(r, g, b, a); }

void drawPolygon(ImDrawList* dl, const View& view, const Cage& cage, const Points& P, ImU32 color, float thickness) {
  const Index m = P.rows();
  auto line = [&](Index i, Index j) {
    dl->AddLine(im(view.toScreen(P.row(i).transpose())), im(view.toScreen(P.row(j).transpose())), color, thickness);
  };
  if (!cage.edges.empty()) {
    for (const auto& e : cage.edges)
      if (e[0] < m && e[1] < m) line(e[0], e[1]);
  } else {
    for (Index i = 0; i + 1 < m; ++i) line(i, i + 1);
    if (cage.closed && m >= 3) line(m - 1, 0);
  }
}

void drawHandle(ImDrawList* dl, const Vec2& s, bool selected, bool active) {
  const ImVec2 c = im(s);
  if (active) dl->AddCircle(c, 11.0f, rgba(255, 230, 80), 20, 2.5f);
  dl->AddCircleFilled(c, 6.5f, rgba(20, 20, 28));
  dl->AddCircleFilled(c, 5.0f, selected ? rgba(255, 150, 30) : rgba(245, 245, 250));
}

void drawPoseOverlay(AppState& state, ImDrawList* dl) {
  const View& view = state.view;
  const Points P = posedControls(state.boundCage.C, state.pose);
  if (state.show.foldovers && state.mesh.hasWeights() && state.deformReport.flippedTriangles > 0) {
    const Points& F = state.mesh.deformedVertices();
    const auto& J = state.mesh.jacobians();
    const auto& T = state.mesh.triangles();
    for (std::size_t t = 0; t < T.size() && static_cast<Index>(t) < J.size(); ++t)
      if (J(static_cast<Index>(t)) <= 0.0)
        dl->AddTriangleFilled(im(view.toScreen(F.row(T[t][0]).transpose())), im(view.toScreen(F.row(T[t][1]).transpose())),
                              im(view.toScreen(F.row(T[t][2]).transpose())), rgba(255, 0, 60, 110));
  }
  if (state.show.samples) {
    const SampleSet& S = state.samples;
    const bool deformed = state.session && !isRestPose(state.pose) && state.session->W.rows() == S.size();
    const Points X = deformed ? deformPoints(state.session->W, S.X, state.boundCage.C, state.pose) : S.X;
    for (Index s = 0; s < X.rows(); ++s) {
      const Rgba c = app::sampleColor(S.kind[static_cast<std::size_t>(s)]);
      dl->AddCircleFilled(im(view.toScreen(X.row(s).transpose())), 1.8f, rgba(c.r, c.g, c.b, 200), 6);
    }
  }
  if (state.show.restCage) drawPolygon(dl, view, state.boundCage, state.boundCage.C, rgba(200, 200, 220, 120), 1.0f);
  if (state.show.cage) {
    drawPolygon(dl, view, state.boundCage, P, rgba(20, 20, 28, 200), 4.0f);
    drawPolygon(dl, view, state.boundCage, P, rgba(255, 160, 40), 2.0f);
  }
  for (Index i = 0; i < P.rows(); ++i) {
    const bool selected = std::find(state.selection.begin(), state.selection.end(), i) != state.selection.end();
    const Vec2 s = view.toScreen(P.row(i).transpose());
    drawHandle(dl, s, selected, i == state.activeControl);
    const double theta = state.pose.empty() ? 0.0 : state.pose[static_cast<std::size_t>(i)].rotate;
    if (theta != 0.0)  // a short tick showing the handle's rotation
      dl->AddLine(im(s), im(s + 16.0 * Vec2(std::cos(theta), -std::sin(theta))), rgba(255, 230, 80), 2.0f);
  }
  if (state.poseTool.selectingRect()) {
    const Vec2 a = view.toScreen(state.poseTool.rectStart()), b = view.toScreen(state.poseTool.rectEnd());
    dl->AddRectFilled(im(a.cwiseMin(b)), im(a.cwiseMax(b)), rgba(120, 170, 255, 40));
    dl->AddRect(im(a.cwiseMin(b)), im(a.cwiseMax(b)), rgba(120, 170, 255, 220));
  }
}

void drawBrushRing(AppState& state, ImDrawList* dl) {
  if (!state.canvasHovered && !state.brushTool.active()) return;
  const ImVec2 c = im(state.view.toScreen(state.mouseImage));
  const float r = static_cast<float>(state.brush.radius * state.view.zoom);
  const bool subtract = state.brush.subtract != ImGui::GetIO().KeyCtrl;
  dl->AddCircle(c, r, rgba(0, 0, 0, 160), 48, 3.0f);
  dl->AddCircle(c, r, subtract ? rgba(120, 190, 255) : rgba(255, 255, 255), 48, 1.5f);
  dl->AddLine({c.x - 4, c.y}, {c.x + 4, c.y}, rgba(255, 255, 255));
  if (!subtract) dl->AddLine({c.x, c.y - 4}, {c.x, c.y + 4}, rgba(255, 255, 255));
  if (state.brushTool.active() && state.session) {  // samples touched by this stroke
    const auto& painted = state.brushTool.painted();
    const SampleSet& S = state.session->samples;
    for (std::size_t s = 0; s < painted.size(); ++s)
      if (painted[s]) dl->AddCircleFilled(im(state.view.toScreen(S.X.row(static_cast<Index>(s)).transpose())), 1.5f, rgba(255, 255, 255, 150), 4);
  }
}

void drawCageToolOverlay(AppState& state, ImDrawList* dl) {
  const View& view = state.view;
  const Cage& cage = state.cage;
  const bool invalid = cage.closed && !state.cageValid;
  const ImU32 color = invalid ? rgba(255, 60, 60) : cage.closed ? rgba(80, 230, 140) : rgba(120, 200, 255);
  drawPolygon(dl, view, cage, cage.C, rgba(20, 20, 28, 200), 4.0f);
  drawPolygon(dl, view, cage, cage.C, color, 2.0f);
  if (!cage.closed && cage.size() > 0 && state.canvasHovered)  // rubber band to the mouse
    dl->AddLine(im(view.toScreen(cage.C.row(cage.size() - 1).transpose())), im(view.toScreen(state.mouseImage)),
                rgba(120, 200, 255, 120), 1.0f);
  for (Index i = 0; i < cage.size(); ++i) {
    const ImVec2 s = im(view.toScreen(cage.C.row(i).transpose()));
    const bool first = i == 0 && !cage.closed;
    dl->AddCircleFilled(s, first ? 8.0f : 6.0f, rgba(20, 20, 28));
    dl->AddCircleFilled(s, first ? 6.5f : 4.5f, i == state.cageTool.selected() ? rgba(255, 150, 30) : color);
  }
  if (!state.cageStatus.empty()) {
    const ImVec2 p = im(view.canvasMin + Vec2(12, 12));
    const ImVec2 size = ImGui::CalcTextSize(state.cageStatus.c_str());
    dl->AddRectFilled({p.x - 6, p.y - 4}, {p.x + size.x + 6, p.y + size.y + 4}, rgba(20, 20, 28, 220), 4.0f);
    dl->AddText(p, invalid ? rgba(255, 110, 110) : rgba(200, 225, 255), state.cageStatus.c_str());
  }
}

}  // namespace

void drawCanvasOverlay(AppState& state) {
  if (state.source.empty()) return;
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const View& view = state.view;
  dl->PushClipRect(im(view.canvasMin), im(view.canvasMin + view.canvasSize), true);
  if (!showsWarp(state))  // outline of the picture at rest
    dl->AddRect(im(view.toScreen(Vec2(-0.5, -0.5))),
                im(view.toScreen(Vec2(state.source.width - 0.5, state.source.height - 0.5))), rgba(90, 90, 105), 0.0f, 0, 1.0f);
  if (state.tool == Tool::Cage) {
    drawCageToolOverlay(state, dl);
  } else if (state.bound) {
    drawPoseOverlay(state, dl);
    if (state.tool == Tool::Brush) drawBrushRing(state, dl);
  }
  dl->PopClipRect();
}

}  // namespace kc::ui
