// Overlays of the canvas (canvas.h): drawn in screen space on ImGui's background draw list, so
// they sit above the GL picture and below the panels.
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "kc/app/heatmap.h"
#include "kc/core/spatial_grid.h"
#include "kc/ui/edits.h"
#include "kc/ui/canvas.h"
#include "kc/ui/tools/pose_tool.h"
#include "overlay_draw.h"

namespace kc::ui {
namespace {

using overlay::im;
using overlay::rgba;

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

/// Numbers of the points of P (#P×2, image pixels) near the mouse, or of all of them; the nearest
/// point's beside it, the others' moved off it where they would cover it (tagPlaces).
void drawPointNumbers(const AppState& state, ImDrawList* dl, const Points& P, bool all, ImU32 color) {
  if (!all && !state.canvasHovered) return;
  const double radius = 12.0 / state.view.zoom;
  std::vector<std::pair<double, Index>> shown;  // (distance to the mouse, point)
  for (Index i = 0; i < P.rows(); ++i)
    if (const double d = (P.row(i).transpose() - state.mouseImage).norm(); all || d <= radius) shown.emplace_back(d, i);
  std::sort(shown.begin(), shown.end());
  std::vector<overlay::Tag> tags;
  for (const auto& [d, i] : shown) {
    const Vec2 s = state.view.toScreen(P.row(i).transpose());
    tags.push_back({ImVec2(float(s.x()) + 9.0f, float(s.y()) - 20.0f), std::to_string(i), color});
  }
  overlay::drawTags(dl, tags);
}

/// A control's handle at screen point s, `scale` times its full size (handleScales).
constexpr double kHandleRadius = 6.5;
void drawHandle(ImDrawList* dl, const Vec2& s, bool selected, bool active, double scale) {
  const ImVec2 c = im(s);
  const float k = static_cast<float>(scale);
  if (active) dl->AddCircle(c, 11.0f * k, rgba(255, 230, 80), 20, 2.5f);
  dl->AddCircleFilled(c, float(kHandleRadius) * k, rgba(20, 20, 28));
  dl->AddCircleFilled(c, 5.0f * k, selected ? rgba(255, 150, 30) : rgba(245, 245, 250));
}

/// The rows of P (image pixels) on screen.
Points screenPoints(const View& view, const Points& P) {
  Points S(P.rows(), 2);
  for (Index i = 0; i < P.rows(); ++i) S.row(i) = view.toScreen(P.row(i).transpose()).transpose();
  return S;
}

/// Colour of a local spacing h on the sample plot's scale [lo, hi] (logarithmic): orange where the
/// samples lie closest, through yellow, to blue where they lie farthest apart.
ImU32 spacingColor(double h, double lo, double hi, int alpha = 220) {
  const double t = hi > lo ? std::clamp(std::log(h / lo) / std::log(hi / lo), 0.0, 1.0) : 1.0;
  const auto mix = [](double a, double b, double u) { return static_cast<int>(std::lround(a + (b - a) * u)); };
  if (t < 0.5) return rgba(mix(255, 250, 2 * t), mix(90, 225, 2 * t), mix(30, 60, 2 * t), alpha);
  return rgba(mix(250, 70, 2 * t - 1), mix(225, 150, 2 * t - 1), mix(60, 255, 2 * t - 1), alpha);
}

/// The sample plot's legend in the canvas's lower left corner: a colour bar from the smallest to
/// the largest spacing, or the kinds' colours.
void drawSampleLegend(const AppState& state, ImDrawList* dl, bool bySpacing, double lo, double hi) {
  const float line = ImGui::GetTextLineHeight();
  const ImVec2 origin = im(state.view.canvasMin + Vec2(12, state.view.canvasSize.y() - 12 - 2.6 * line));
  char text[96];
  if (bySpacing) {
    std::snprintf(text, sizeof text, "Sample spacing (%ld samples)", long(state.bound->samples.size()));
    const float width = std::max(ImGui::CalcTextSize("0000.0 px (narrow places)    0000.0 px").x, ImGui::CalcTextSize(text).x);
    dl->AddRectFilled({origin.x - 6, origin.y - 4}, {origin.x + width + 6, origin.y + 2.6f * line + 4}, rgba(20, 20, 28, 220), 4.0f);
    dl->AddText(origin, rgba(230, 230, 240), text);
    const float y0 = origin.y + line + 2, y1 = y0 + 0.5f * line;
    const int steps = 40;
    for (int k = 0; k < steps; ++k) {
      const double h = lo * std::pow(hi / lo, (k + 0.5) / steps);
      dl->AddRectFilled({origin.x + width * k / steps, y0}, {origin.x + width * (k + 1) / steps, y1}, spacingColor(h, lo, hi, 255));
    }
    std::snprintf(text, sizeof text, "%.1f px (narrow places)", lo);
    dl->AddText({origin.x, y1 + 1}, rgba(230, 230, 240), text);
    std::snprintf(text, sizeof text, "%.1f px", hi);
    dl->AddText({origin.x + width - ImGui::CalcTextSize(text).x, y1 + 1}, rgba(230, 230, 240), text);
    return;
  }
  static constexpr SampleKind kinds[] = {SampleKind::Control, SampleKind::Edge, SampleKind::Line, SampleKind::Interior,
                                         SampleKind::Exterior};
  std::snprintf(text, sizeof text, "Samples (%ld), spacing %.1f px", long(state.bound->samples.size()), hi);
  const ImVec2 title = ImGui::CalcTextSize(text);
  float width = 0.0f;
  for (SampleKind k : kinds) width += 14.0f + ImGui::CalcTextSize(std::string(toString(k)).c_str()).x + 10.0f;
  width = std::max(width, title.x);
  dl->AddRectFilled({origin.x - 6, origin.y - 4}, {origin.x + width + 6, origin.y + 2.2f * line + 4}, rgba(20, 20, 28, 220), 4.0f);
  dl->AddText(origin, rgba(230, 230, 240), text);
  float x = origin.x;
  const float y = origin.y + 1.2f * line;
  for (SampleKind k : kinds) {
    const Rgba c = app::sampleColor(k);
    dl->AddCircleFilled({x + 5, y + 0.5f * line}, 4.0f, rgba(c.r, c.g, c.b), 10);
    const std::string name(toString(k));
    dl->AddText({x + 14, y}, rgba(230, 230, 240), name.c_str());
    x += 14.0f + ImGui::CalcTextSize(name.c_str()).x + 10.0f;
  }
}

/// The bound session's samples (deformed with the pose), coloured by their local spacing when it
/// varies (state.bound->sampleSpacing) and show.sampleSpacing is on, else by kind; with a legend.
void drawSamples(const AppState& state, ImDrawList* dl) {
  const SampleSet& S = state.bound->samples;
  if (S.size() == 0) return;
  const bool deformed = state.session && !isRestPose(state.pose) && state.session->W.rows() == S.size();
  const Points X = deformed ? deformPoints(state.session->W, S.X, state.bound->cage.C, state.pose) : S.X;
  const bool known = state.bound->sampleSpacing.size() == S.size();
  const double lo = known ? state.bound->sampleSpacing.minCoeff() : state.bound->spacing;
  const double hi = known ? state.bound->sampleSpacing.maxCoeff() : state.bound->spacing;
  const bool bySpacing = state.show.sampleSpacing && known && lo < hi - 0.05;
  for (Index s = 0; s < X.rows(); ++s) {
    ImU32 color;
    if (bySpacing) {
      color = spacingColor(state.bound->sampleSpacing(s), lo, hi);
    } else {
      const Rgba c = app::sampleColor(S.kind[static_cast<std::size_t>(s)]);
      color = rgba(c.r, c.g, c.b, 200);
    }
    dl->AddCircleFilled(im(state.view.toScreen(X.row(s).transpose())), 1.8f, color, 6);
  }
  drawSampleLegend(state, dl, bySpacing, lo, hi);
}

void drawPoseOverlay(AppState& state, ImDrawList* dl) {
  const View& view = state.view;
  const Points P = posedControls(state.bound->cage.C, state.pose);
  if (state.show.foldovers && state.mesh.hasWeights() && state.deformReport.flippedTriangles > 0) {
    const Points& F = state.mesh.deformedVertices();
    const auto& J = state.mesh.jacobians();
    const auto& T = state.mesh.triangles();
    for (std::size_t t = 0; t < T.size() && static_cast<Index>(t) < J.size(); ++t)
      if (J(static_cast<Index>(t)) <= 0.0)
        dl->AddTriangleFilled(im(view.toScreen(F.row(T[t][0]).transpose())), im(view.toScreen(F.row(T[t][1]).transpose())),
                              im(view.toScreen(F.row(T[t][2]).transpose())), rgba(255, 0, 60, 110));
  }
  if (state.show.samples) drawSamples(state, dl);
  if (state.show.restCage) drawPolygon(dl, view, state.bound->cage, state.bound->cage.C, rgba(200, 200, 220, 120), 1.0f);
  if (state.show.cage) {
    drawPolygon(dl, view, state.bound->cage, P, rgba(20, 20, 28, 200), 4.0f);
    drawPolygon(dl, view, state.bound->cage, P, rgba(255, 160, 40), 2.0f);
  }
  const Points S = screenPoints(view, P);
  const Eigen::VectorXd scale = handleScales(S, kHandleRadius);
  for (Index i = 0; i < P.rows(); ++i) {
    const bool selected = std::find(state.selection.begin(), state.selection.end(), i) != state.selection.end();
    const Vec2 s = S.row(i).transpose();
    drawHandle(dl, s, selected, i == state.activeControl, scale(i));
    const double theta = state.pose.empty() ? 0.0 : state.pose[static_cast<std::size_t>(i)].rotate;
    if (theta != 0.0)  // a short tick showing the handle's rotation
      dl->AddLine(im(s), im(s + 16.0 * Vec2(std::cos(theta), -std::sin(theta))), rgba(255, 230, 80), 2.0f);
  }
  drawPointNumbers(state, dl, P, false, rgba(255, 255, 255));
  if (state.selection.size() >= 2 && state.tool == Tool::Pose) {  // the pivot of the selection's rotation
    const ImVec2 c = im(view.toScreen(selectionPivot(state)));
    for (const ImU32 color : {rgba(20, 20, 28), rgba(120, 230, 255)}) {
      const float w = color == rgba(20, 20, 28) ? 4.0f : 2.0f;
      dl->AddLine({c.x - 9, c.y}, {c.x + 9, c.y}, color, w);
      dl->AddLine({c.x, c.y - 9}, {c.x, c.y + 9}, color, w);
    }
    dl->AddCircle(c, 6.0f, rgba(120, 230, 255), 16, 1.5f);
  }
  if (state.poseTool.rotating()) {  // the angle turned so far, by the mouse
    char text[32];
    std::snprintf(text, sizeof text, "%+.1f\xc2\xb0", state.poseTool.angle() * 180.0 / std::numbers::pi);
    const ImVec2 p = im(view.toScreen(state.mouseImage) + Vec2(16, -22));
    const ImVec2 size = ImGui::CalcTextSize(text);
    dl->AddRectFilled({p.x - 4, p.y - 2}, {p.x + size.x + 4, p.y + size.y + 2}, rgba(20, 20, 28, 220), 3.0f);
    dl->AddText(p, rgba(255, 230, 80), text);
  }
  if (state.poseTool.selectingRect()) {
    const Vec2 a = view.toScreen(state.poseTool.rectStart()), b = view.toScreen(state.poseTool.rectEnd());
    dl->AddRectFilled(im(a.cwiseMin(b)), im(a.cwiseMax(b)), rgba(120, 170, 255, 40));
    dl->AddRect(im(a.cwiseMin(b)), im(a.cwiseMax(b)), rgba(120, 170, 255, 220));
  }
}

/// A brush's outline at the mouse (radius in image pixels; `core` > 0 also draws the inner ring
/// where a soft brush starts to fade); a minus sign when it takes away.
void drawRing(const AppState& state, ImDrawList* dl, double radius, double core, bool subtract) {
  const ImVec2 c = im(state.view.toScreen(state.mouseImage));
  const float r = static_cast<float>(radius * state.view.zoom);
  dl->AddCircle(c, r, rgba(0, 0, 0, 160), 48, 3.0f);
  dl->AddCircle(c, r, subtract ? rgba(120, 190, 255) : rgba(255, 255, 255), 48, 1.5f);
  if (core > 0.0 && core < radius) dl->AddCircle(c, static_cast<float>(core * state.view.zoom), rgba(255, 255, 255, 110), 48, 1.0f);
  dl->AddLine({c.x - 4, c.y}, {c.x + 4, c.y}, rgba(255, 255, 255));
  if (!subtract) dl->AddLine({c.x, c.y - 4}, {c.x, c.y + 4}, rgba(255, 255, 255));
}

void drawBrushRing(AppState& state, ImDrawList* dl) {
  if (!state.canvasHovered && !state.brushTool.active()) return;
  drawRing(state, dl, state.brush.radius, 0.0, state.brush.subtract != ImGui::GetIO().KeyCtrl);
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
  const bool complete = cageComplete(cage);
  const bool invalid = complete && !state.cageValid;
  const ImU32 color = invalid ? rgba(255, 60, 60) : complete ? rgba(80, 230, 140) : rgba(120, 200, 255);
  drawPolygon(dl, view, cage, cage.C, rgba(20, 20, 28, 200), 4.0f);
  drawPolygon(dl, view, cage, cage.C, color, 2.0f);
  if (!complete && cage.size() > 0 && state.canvasHovered)  // rubber band to the mouse
    dl->AddLine(im(view.toScreen(cage.C.row(cage.size() - 1).transpose())), im(view.toScreen(state.mouseImage)),
                rgba(120, 200, 255, 120), 1.0f);
  const Points S = screenPoints(view, cage.C);
  const Eigen::VectorXd scale = handleScales(S, 6.0);
  for (Index i = 0; i < cage.size(); ++i) {
    const ImVec2 s = im(S.row(i).transpose());
    const bool first = i == 0 && !complete;
    const float k = static_cast<float>(scale(i));
    dl->AddCircleFilled(s, (first ? 8.0f : 6.0f) * k, rgba(20, 20, 28));
    dl->AddCircleFilled(s, (first ? 6.5f : 4.5f) * k, i == state.cageTool.selected() ? rgba(255, 150, 30) : color);
  }
  // Every point's number while the cage is invalid (the message names points), else near the mouse.
  drawPointNumbers(state, dl, cage.C, invalid, invalid ? rgba(255, 150, 150) : rgba(255, 255, 255));
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
  // The image border: what an export covers (a warped picture may reach beyond it).
  dl->AddRect(im(view.toScreen(Vec2(-0.5, -0.5))), im(view.toScreen(Vec2(state.source.width - 0.5, state.source.height - 0.5))),
              rgba(150, 150, 170, 200), 0.0f, 0, 1.0f);
  if (state.showOriginal && state.bound) {  // before/after: the original picture and the rest cage
    drawPolygon(dl, view, state.bound->cage, state.bound->cage.C, rgba(255, 160, 40, 160), 1.5f);
    const char* text = "Original (release O to see the warp)";
    const ImVec2 p = im(view.canvasMin + Vec2(12, 12));
    const ImVec2 size = ImGui::CalcTextSize(text);
    dl->AddRectFilled({p.x - 6, p.y - 4}, {p.x + size.x + 6, p.y + size.y + 4}, rgba(20, 20, 28, 220), 4.0f);
    dl->AddText(p, rgba(255, 220, 120), text);
  } else if (state.tool == Tool::Cage) {
    drawCageToolOverlay(state, dl);
  } else if (state.tool == Tool::Lines) {
    if (state.bound) drawPolygon(dl, view, state.bound->cage, state.bound->cage.C, rgba(255, 160, 40, 200), 2.0f);
    else drawCageToolOverlay(state, dl);
  } else if (state.bound && state.hideCage) {  // a tight cage's outline and handles cover what it bends
    const char* text = "Without the cage (release H)";
    const ImVec2 p = im(view.canvasMin + Vec2(12, 12));
    const ImVec2 size = ImGui::CalcTextSize(text);
    dl->AddRectFilled({p.x - 6, p.y - 4}, {p.x + size.x + 6, p.y + size.y + 4}, rgba(20, 20, 28, 220), 4.0f);
    dl->AddText(p, rgba(255, 220, 120), text);
  } else if (state.bound) {
    dl->PopClipRect();
    drawRigidityOverlay(state);  // under the cage and the handles
    dl->PushClipRect(im(view.canvasMin), im(view.canvasMin + view.canvasSize), true);
    drawPoseOverlay(state, dl);
    if (state.tool == Tool::Brush) drawBrushRing(state, dl);
    if (state.tool == Tool::Rigid && (state.canvasHovered || state.rigidTool.active()))
      drawRing(state, dl, state.rigidBrush.radius, (1.0 - state.rigidBrush.softness) * state.rigidBrush.radius,
               state.rigidBrush.erase != ImGui::GetIO().KeyCtrl);
  }
  dl->PopClipRect();
  if (!state.showOriginal && !state.hideCage && state.tool != Tool::Cage) drawLinesOverlay(state);
}

Eigen::VectorXd handleScales(const Points& S, double radius) {
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(S.rows());
  if (S.rows() < 2 || !(radius > 0.0)) return scale;
  const SpatialGrid grid(S, 2.0 * radius);
  for (Index i = 0; i < S.rows(); ++i) {
    double nearest2 = 4.0 * radius * radius;
    grid.forEachWithin(S.row(i).transpose(), 2.0 * radius, [&](Index j, double d2) {
      if (j != i) nearest2 = std::min(nearest2, d2);
    });
    scale(i) = std::clamp(0.5 * std::sqrt(nearest2) / radius, kMinHandleScale, 1.0);
  }
  return scale;
}

Points tagPlaces(const Points& at, const Points& size) {
  Points placed = at;
  const auto overlap = [&](Index a, Index b) {  // boxes a and b (placed) intersect
    return placed(a, 0) < placed(b, 0) + size(b, 0) && placed(b, 0) < placed(a, 0) + size(a, 0) &&
           placed(a, 1) < placed(b, 1) + size(b, 1) && placed(b, 1) < placed(a, 1) + size(a, 1);
  };
  // At most kMaxMoves moves per tag: tags piled in one column (all the numbers of a big cage seen
  // from afar) would otherwise cost O(n³); past that a tag may cover another.
  constexpr Index kMaxMoves = 8;
  for (Index i = 1; i < at.rows(); ++i)
    for (Index moves = 0; moves < std::min(i, kMaxMoves); ++moves) {  // each move clears one placed box
      Index blocker = -1;
      for (Index j = 0; j < i && blocker < 0; ++j)
        if (overlap(i, j)) blocker = j;
      if (blocker < 0) break;
      placed(i, 1) = placed(blocker, 1) + size(blocker, 1) + 2.0;
    }
  return placed;
}

}  // namespace kc::ui
