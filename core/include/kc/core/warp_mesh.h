#pragma once
/// The warp mesh: a triangle grid over the image whose vertices carry compact weights, deformed by
/// linear blend skinning (thesis 3.37) and rendered by the rasterizer (thesis 6.3.3).
///
/// Use: build once per (image size, cage, options); evaluate the weights at restVertices() (e.g.
/// `CoordinateField::weightsAt`) and hand them to setWeights(); then deform(pose) per pose
/// (one sparse product, parallel) and render(source).

#include <Eigen/SparseCore>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/deform.h"
#include "kc/core/exterior_untangle.h"
#include "kc/core/exterior_weights.h"
#include "kc/core/rasterize.h"
#include "kc/core/types.h"

namespace kc {

/// What happens to the image outside the cage.
enum class OutsideMode {
  /// The image border stays pinned; the background between cage and border stretches smoothly:
  /// outside the cage each control's weight is its harmonic extension to the border and a fixed
  /// anchor takes the rest (exterior_weights.h), and the motion fades out within a band around the
  /// cage that grows with the pose (WarpMeshOptions::fadeBand). Inside the cage the field's
  /// weights are used.
  Pinned,
  Deform,       ///< Everything follows the weights (kernel coordinates cover the whole image).
  Fixed,        ///< Outside stays in place (like GIMP's cage tool): deformed inside drawn over the original.
  Transparent,  ///< Only the inside of the cage is drawn.
};

template <>
struct EnumNames<OutsideMode> {
  static constexpr std::array<std::pair<OutsideMode, std::string_view>, 4> table{
      {{OutsideMode::Pinned, "pinned"},
       {OutsideMode::Deform, "deform"}, {OutsideMode::Fixed, "fixed"}, {OutsideMode::Transparent, "transparent"}}};
};

struct WarpMeshOptions {
  double spacing = 4.0;          ///< Grid spacing in pixels (≥ 0.5).
  /// Keep |w_i(v)| > keepThreshold / m (LBC paper, Table 1, whose weights are non-negative; we
  /// compare magnitudes so that kernel coordinates' small negative lobes, which carry linear
  /// precision, are kept too).
  double keepThreshold = 1e-3;
  OutsideMode outside = OutsideMode::Pinned;
  /// Pinned, Fixed and Transparent modes: a mesh whose edges follow the cage
  /// (cage_conforming_grid.h): every triangle lies wholly inside or outside and points on the cage
  /// take the field's weights, so the picture inside the cage depends only on the field and the
  /// fold repair (repairFolds) can move the outside without touching it. No triangle of the inside
  /// spans a gap of the cage however narrow (the two legs of a figure drawn 3 px apart), so pulling
  /// one side does not drag the picture of the other. Fixed and Transparent keep only the inside's
  /// triangles. Off: the regular grid, whose triangles straddle the cage (the repair can then move
  /// only vertices of triangles wholly outside, and folds across the cage stay).
  bool followCage = true;
  /// Pinned mode: after the harmonic extension, untangle the background where it folds
  /// (exterior_untangle.h), moving only vertices strictly outside the cage (border vertices other
  /// than the corners may slide along the border or move outward, where the cage reaches it).
  bool repairFolds = true;
  /// Pinned mode: open sticks (edges on no loop: a stick figure's limbs) carry the picture around
  /// them. Vertices closer to a stick than this fraction of its length (at least 1.5 grid-cell
  /// diagonals) take the coordinate field's weights, and the background's harmonic extension
  /// starts at that band's edge (exterior_weights.h). 0: the extension starts on the sticks.
  double stickBand = 0.2;
  /// Pinned mode: the background's motion fades out with the distance r from the cage (from the
  /// edge of the outside, which a stick band widens). Per pose, with D the largest displacement
  /// of a vertex on that edge (the cage's outline) and B = fadeBand · D, a vertex outside the cage
  /// moves by φ(r / B) times its harmonic displacement, φ(t) = 1 − 3t² + 2t³ for t < 1, else 0:
  /// φ is 1 with zero slope at the cage, so the stretch next to the cage is the harmonic one, and
  /// 0 with zero slope at r = B, so what lies farther than B from the cage stays where it was.
  /// Along the distance's gradient the fade adds a stretch or squeeze of at most 1.5·D/B to the
  /// harmonic one (|φ'| ≤ 1.5): 0.75 at the default 2, the smallest width that leaves what lies
  /// beyond twice the drag untouched without folding a drag straight into the background.
  /// 0: no fade (the stretch reaches the image border, the plain harmonic extension).
  double fadeBand = 2.0;
};

/// Compact (sparse) vs dense storage of the vertex weights (LBC paper Table 1).
struct CompactWeightsReport {
  Index vertices = 0;
  Index controls = 0;
  Index nonZeros = 0;            ///< Entries kept.
  double meanPerVertex = 0.0;    ///< Mean kept entries per vertex.
  Index maxPerVertex = 0;
  std::size_t compactBytes = 0;  ///< CSR: values (8 B) + column indices (4 B) + row offsets (4 B).
  std::size_t denseBytes = 0;    ///< #V·m·8 B.
  double droppedMass = 0.0;      ///< max_v Σ |dropped entries| before renormalization.
  double seconds = 0.0;
};

/// Result of one deformation.
struct DeformReport {
  Index flippedTriangles = 0;    ///< Triangles with det J ≤ 0 (fold-overs), among drawn triangles.
  double flippedArea = 0.0;      ///< Rest area (px²) of the flipped triangles.
  double minJacobian = 0.0;      ///< min det J over drawn triangles (1 = area kept).
  double maxJacobian = 0.0;
  /// Pinned mode's fold repair (exterior_untangle.h): triangles of the outside that the harmonic
  /// extension folded (det J ≤ 0), those still folded after the repair, the vertices it moved
  /// (its region) and its time (included in `seconds`). All 0 when the repair is off or nothing folds.
  Index harmonicFolds = 0, repairedFolds = 0, repairVertices = 0;
  Index repairBorderVertices = 0;  ///< Of repairVertices, border vertices (slid along the border or moved outward).
  /// Pinned mode: the width B (px) of the band within which the background's motion fades out
  /// (WarpMeshOptions::fadeBand); 0 when the fade is off or the cage's outline did not move.
  double fadeWidth = 0.0;
  bool repairWarmStart = false;    ///< The repair started from the previous picture (DeformPass::Live).
  double repairSeconds = 0.0;
  double seconds = 0.0;
};

/// How deform() repairs the pinned background's folds (exterior_untangle.h).
enum class DeformPass {
  /// The full repair: the continuation from rest. The result depends on the pose only (exports,
  /// the picture after a drag is released).
  Final,
  /// While a pose is dragged: when the previous deform() left no fold outside the cage, the
  /// continuation starts from its picture and takes a few steps (ExteriorRepairOptions::warmSteps)
  /// instead of many from rest; if that leaves a fold, the repair from rest runs. Both with a
  /// quarter of the Final pass's work budget, so a pose that is hard or impossible to untangle
  /// costs less per frame (it may keep folds until the release). The result can differ from the
  /// Final one (it depends on the drag's path), so a Final pass follows the release.
  Live,
};

class WarpMesh {
 public:
  using SparseWeights = CompactWeights;

  WarpMesh() = default;
  /// Grid over [−0.5, w−0.5]×[−0.5, h−0.5] (pixel centres at integers) with about `spacing`
  /// pixels between vertices, two triangles per cell (with followCage, re-triangulated along the
  /// cage). In Fixed/Transparent modes only triangles inside the cage (without followCage: that
  /// can meet it) are kept; in Pinned mode the exterior weights are solved here (one sparse
  /// factorization, exteriorWeights()). Throws std::invalid_argument on bad sizes or options.
  WarpMesh(int width, int height, const Cage& cage, const WarpMeshOptions& options = {});

  int width() const { return m_width; }
  int height() const { return m_height; }
  const WarpMeshOptions& options() const { return m_options; }
  const Cage& cage() const { return m_cage; }
  /// #V×2 rest positions: where to evaluate weights. The grid vertices in row-major order (with
  /// followCage, the Pinned default, followed by the points on the cage, cage_conforming_grid.h).
  const Points& restVertices() const { return m_rest; }
  /// Triangles that are drawn (#T), in drawing order (later on top): row-major grid order; in
  /// Pinned mode the triangles wholly outside the cage come first, then those across the cage,
  /// then those inside, so the inside is drawn over the stretched background (with followCage:
  /// outside, then inside; none is across).
  const Triangles& triangles() const { return m_triangles; }
  /// Pinned mode: triangles()[0..outsideTriangles()) lie wholly outside the cage (all three
  /// vertices exterior; with followCage, every triangle outside); 0 in the other modes.
  Index outsideTriangles() const { return m_outsideTriangles; }

  /// Stores weights W (#V×m, dense, at restVertices()) compactly: entries with |w| ≤ keepThreshold/m
  /// are dropped and each row is renormalized to sum to 1 (partition of unity). In Pinned mode the
  /// rows of vertices outside the cage are taken from exteriorWeights() instead (W's rows there
  /// are not used) and weights() has m+1 columns, the last one the fixed anchor. Throws on shape
  /// mismatch or non-finite weights.
  CompactWeightsReport setWeights(const Weights& W);
  /// Same, from weights already sparse (#V×m); they are thresholded and renormalized too.
  CompactWeightsReport setWeights(const SparseWeights& W);
  bool hasWeights() const { return m_weights.rows() > 0; }
  /// #V×m compact weights (#V×(m+1) in Pinned mode: column m is the anchor, transform = identity).
  const SparseWeights& weights() const { return m_weights; }
  /// Pinned mode: the exterior classification and harmonic-extension weights (null otherwise).
  /// Rows as restVertices() (with followCage the points on the cage are not exterior: empty rows).
  const ExteriorWeights* exteriorWeights() const { return m_exterior.get(); }

  /// f(v) = Σ_i w_i(v) T_i v (3.37) at every vertex (plus a(v)·v for the pinned anchor) — one sparse product, parallel over vertices —
  /// then, in Pinned mode, the fold repair of the triangles outside the cage, and det J per triangle (the piecewise-linear counterpart of 3.44: deformed / rest signed
  /// area). `pass`: see DeformPass. Throws std::invalid_argument for a bad pose or when no weights are set.
  DeformReport deform(const Pose& pose, DeformPass pass = DeformPass::Final);
  /// Deformed vertices (#V×2) of the last deform() (rest positions before the first).
  const Points& deformedVertices() const { return m_deformed; }
  /// det J per triangle of the last deform() (#T).
  const Eigen::VectorXd& jacobians() const { return m_jacobian; }

  /// Renders `source` (width()×height()) through the deformed mesh according to the outside
  /// mode; output has the source's size.
  Image render(const Image& source, const RasterOptions& options = {}, RasterReport* report = nullptr) const;

 private:
  /// Pinned mode: the cage-conforming mesh over the grid xs × ys and its exterior weights.
  void buildPinned(const std::vector<double>& xs, const std::vector<double>& ys);
  /// Fixed and Transparent modes with followCage: the inside triangles of the cage-conforming mesh.
  void buildInside(const std::vector<double>& xs, const std::vector<double>& ys);
  /// Pinned mode with repairFolds: the fold repair's topology (vertices outside the cage and off
  /// the border of the grid xs × ys are movable).
  void buildRepair(const std::vector<double>& xs, const std::vector<double>& ys);
  /// Pinned mode with fadeBand > 0: each vertex's distance from the edge of the outside.
  void buildFade();
  /// Scales the displacement of the vertices outside the cage by φ(r / B) (fadeBand); returns B.
  double fadeExterior();

  int m_width = 0, m_height = 0;
  WarpMeshOptions m_options;
  Cage m_cage;
  Points m_rest, m_deformed;
  Triangles m_triangles;
  SparseWeights m_weights;
  std::shared_ptr<const ExteriorWeights> m_exterior;  // Pinned mode; shared by copies (immutable)
  Index m_outsideTriangles = 0;  // Pinned mode: triangles[0..m_outsideTriangles) lie outside the cage
  std::shared_ptr<const ExteriorRepairTopology> m_repair;  // Pinned mode with repairFolds; shared by copies (immutable)
  // Pinned mode with fadeBand > 0: per vertex, the distance from the edge of the outside (exterior
  // vertices; 0 elsewhere), and the vertices on that edge (not exterior, next to an exterior one).
  struct Fade {
    std::vector<double> distance;
    std::vector<Index> edge;
  };
  std::shared_ptr<const Fade> m_fade;  // shared by copies (immutable)
  Eigen::VectorXd m_restArea, m_jacobian;
  // The fold repair's last result, the start of a DeformPass::Live repair: positions (#V×2, kept
  // from the first live pass on) and whether it left no fold outside the cage.
  Points m_previous;
  bool m_previousFoldFree = false;
};

/// The grid of vertex positions along one axis covering [−0.5, n−0.5] with steps ≤ spacing.
std::vector<double> gridAxis(int n, double spacing);

/// Smallest automatic warp mesh spacing (px): what a picture up to about 1 megapixel gets.
inline constexpr double kMinAutoMeshSpacing = 4.0;
/// Grid vertices the automatic spacing allows over the whole picture (2¹⁶, a 1024×1024 picture at 4 px).
inline constexpr double kAutoMeshVertices = 65536.0;
/// Automatic mesh spacing per unit of the field's sample spacing h (4 px at the default h = 6 px).
inline constexpr double kAutoMeshPerFieldSpacing = 2.0 / 3.0;

/// The warp mesh spacing for a width×height picture whose field was sampled at spacing h
/// (`fieldSpacing`, px; 0 when unknown):
///   s = max(4, (2/3)·h, √(width·height / 2¹⁶)).
/// The picture term keeps the grid at about 2¹⁶ vertices however many pixels the picture has (a
/// picture scaled by k gets k times the spacing: the same mesh relative to the picture); the
/// field term keeps the default's ratio of mesh to sample spacing (4 px per 6 px), since the
/// field has no detail finer than its samples (σ ≈ h); 4 px is the floor.
double automaticMeshSpacing(int width, int height, double fieldSpacing = 0.0);

}  // namespace kc
