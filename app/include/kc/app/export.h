#pragma once
/// Warping a bound session's image for export, and the session ↔ image path convention. One code
/// path for `kcwarp-cli warp` and the GUI's Export (ARCHITECTURE.md, data flow: core/warp → PNG).

#include <string>

#include "kc/app/field_sampler.h"
#include "kc/app/session.h"
#include "kc/core/rasterize.h"
#include "kc/core/warp_mesh.h"

namespace kc::app {

/// The warp mesh options of a session's picture, the same for `kcwarp-cli warp`, the GUI's export
/// and its display: outside mode `outside`, spacing kc::automaticMeshSpacing(image size, h =
/// weightSpacing(session.params), the sample spacing but for `--init lbc`, whose session records its
/// LBC mesh's spacing: Session::lbcMeshSpacing) — max(4, 2h/3, √(w·h/2¹⁶)) px.
WarpMeshOptions warpMeshOptionsFor(const Session& session, OutsideMode outside = OutsideMode::Pinned);
/// The same before a session exists (a bind about to start): a width×height picture whose field
/// will be sampled at `fieldSpacing` px (0: unknown).
WarpMeshOptions warpMeshOptionsFor(int width, int height, double fieldSpacing, OutsideMode outside = OutsideMode::Pinned);

/// Options of a full-resolution warp; warpMeshOptionsFor(session) gives `kcwarp-cli warp`'s mesh.
struct WarpExportOptions {
  WarpMeshOptions mesh;    ///< Warp mesh spacing and outside mode (pinned).
  RasterOptions raster;    ///< Supersampling and background (transparent).
};

/// What one export did (for the GUI's diagnostics and tests).
struct WarpExportReport {
  CompactWeightsReport weights;
  DeformReport deform;
  RasterReport raster;
  double weightSeconds = 0.0;  ///< Evaluating w at the mesh vertices.
};

/// Builds the warp mesh for the session's image size and cage, evaluates the session's field at
/// its vertices (WarpMesh::setWeights) — the same steps as `kcwarp-cli warp`. Requires a ready
/// field (std::invalid_argument otherwise); an outside mode the session's field cannot do
/// (`deform` without weights outside the cage) is an InputError. When `sampler` is given, the field is evaluated
/// through a FieldSampler at the vertices, which is kept there together with the dense vertex
/// weights (`vertexWeights`, #V×m), so that later edits can update only the changed columns.
WarpMesh buildWarpMesh(const Session& session, const WarpMeshOptions& options = {}, WarpExportReport* report = nullptr,
                       FieldSampler* sampler = nullptr, Weights* vertexWeights = nullptr);

/// The source image warped by `pose` (one handle per control, or empty = rest) at full
/// resolution: buildWarpMesh + deform + render (thesis 3.37, 6.3.3). The output has the source's
/// size. Throws std::invalid_argument when the source size differs from the session's or the
/// pose is unusable.
Image warpSessionImage(const Session& session, const Image& source, const Pose& pose,
                       const WarpExportOptions& options = {}, WarpExportReport* report = nullptr);

/// The image path as stored in a session written to `sessionPath`: relative to its folder when
/// possible, absolute otherwise.
std::string imagePathForSession(const std::string& imagePath, const std::string& sessionPath);
/// The image path of a session file (`stored`, as written in it) resolved against its folder.
std::string resolveSessionImage(const std::string& stored, const std::string& sessionPath);

}  // namespace kc::app
