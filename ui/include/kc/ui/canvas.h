#pragma once
/// The canvas: the picture area behind the panels. Mouse input goes to pan/zoom and to the active
/// tool (only when ImGui does not want the mouse); overlays (cage, control points, samples,
/// fold-overs, brush ring, selection rectangle) are drawn on ImGui's background draw list.

#include "kc/ui/app_state.h"

namespace kc::ui {

/// Sets the canvas rectangle (screen pixels) and fits the view when a new image was opened.
void layoutCanvas(AppState& state, const Vec2& min, const Vec2& size);

/// Reads the mouse (ImGui IO) and drives pan/zoom and the active tool.
void handleCanvasInput(AppState& state);

/// Draws the overlays of the canvas.
void drawCanvasOverlay(AppState& state);

/// The structure lines over the picture: in the line tool at rest, with the selection and the
/// line being drawn; else deformed with the pose (each line through its deformed samples).
/// Parallel groups have their own colour and name.
void drawLinesOverlay(AppState& state);

/// The rigid regions over the picture (in the rigidity tool, else when View > Rigid regions is on):
/// the per-sample rigidity ρ (the stroke being painted, else the session's) as a cyan tint carried
/// by the display mesh, and the rigid polygons of a structure file or session outlined; both
/// follow the warp where the picture is shown deformed.
void drawRigidityOverlay(AppState& state);

/// True when the picture is shown deformed (a bound session, not in the cage or line tool).
bool showsWarp(const AppState& state);

/// Rest position of a point of the deformed picture: the deformed warp-mesh triangle containing
/// `p` (the topmost, i.e. last, one where folded) mapped back barycentrically. False when `p` lies
/// outside the deformed mesh.
bool restPositionOf(const WarpMesh& mesh, const Vec2& p, Vec2& rest);

/// How large to draw each of the points S (#S×2, screen pixels) as a handle of `radius` px: 1 where
/// its nearest neighbour is at least 2·radius away, else half that distance over `radius`, not
/// below kMinHandleScale — so that handles a few pixels apart stay apart on screen at any zoom.
inline constexpr double kMinHandleScale = 0.4;
Eigen::VectorXd handleScales(const Points& S, double radius);

/// Where to draw tags (labels in boxes) so that none covers another: `at` #n×2 the preferred
/// top-left corners, `size` #n×2 the boxes' widths and heights (screen pixels). In row order, each
/// tag keeps its place unless its box overlaps one already placed; then it moves down to just
/// below that box (2 px apart), until it is clear or it has moved 8 times (then it may cover one).
/// Rows earlier in `at` win their place.
Points tagPlaces(const Points& at, const Points& size);

}  // namespace kc::ui
