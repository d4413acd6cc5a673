#pragma once
/// The session: everything needed to reproduce a warp (ARCHITECTURE.md, Session file).

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "kc/app/structure.h"
#include "kc/core/cage.h"
#include "kc/core/deform.h"
#include "kc/core/field/field.h"
#include "kc/core/field/lobe_lift.h"
#include "kc/core/kernel/interpolator.h"
#include "kc/core/lbc/lbc_solver.h"
#include "kc/core/structure/linear_along.h"
#include "kc/core/structure/rigidity.h"
#include "kc/core/types.h"
#include "kc/core/warp_mesh.h"
#include "kc/core/weights/heat_diffusion.h"
#include "kc/core/weights/optimizer.h"
#include "kc/sampling/sampler.h"

namespace kc::app {

/// Default locality length of the kc backend's targets, in sample spacings (Locality::Rule::
/// Spacings). Shorter lengths are more local (the drag area of `kcwarp-cli stats` falls
/// towards the LBC backend's), but targets that fall off within about one sample spacing ring
/// between the samples: 1.5 spacings is the shortest length that does not deepen the lobes.
inline constexpr double kLocalitySpacings = 1.5;

/// How far the kc backend's heat-linear targets reach inside the shape: the locality length ℓ
/// of the screened diffusion (kc::InitOptions::locality), by one of four rules. Resolved to ℓ
/// in pixels, or none, by app::locality (pipeline.h).
struct Locality {
  enum class Rule {
    Off,        ///< Unscreened targets (4.13): smooth, global, harmonic-like.
    Spacings,   ///< ℓ = max(value·spacing, D/4), D the cage's depth (localityLength). The default.
    Pixels,     ///< ℓ = value pixels.
    Automatic,  ///< ℓ = kc::kAutoLocalityFraction of the cage's bounding-box diagonal.
  };
  Rule rule = Rule::Spacings;
  double value = kLocalitySpacings;  ///< Spacings or pixels (finite, > 0) for those rules; unused otherwise.
  bool operator==(const Locality&) const = default;
};

/// Default floor of the kc backend's screened targets (KcParams::targetFloor, kc::floorTargets):
/// the diffused heat's tail below 4% of a sample's weight is dropped before the per-sample
/// optimization. A drag then moves about what the LBC backend's weights move (`kcwarp-cli stats`,
/// locality.drag); lower floors keep more of the tail, higher ones leave the optimizer to restore
/// reproduction with weights far from the control, and deepen the lobes of the unbounded field
/// (the QP's are held by the lobe bound, KcParams::lobeBound; the measurements:
/// docs/notes/measured-constants.md).
inline constexpr double kTargetFloor = 0.04;
/// KcParams::targetFloor lies in [0, kMaxTargetFloor): a floor of 1/2 or more would leave each
/// sample at most one control's target.
inline constexpr double kMaxTargetFloor = 0.5;

/// KcParams::lobeBound lies in [0, kMaxLobeBound].
inline constexpr double kMaxLobeBound = 0.5;

/// Default ε of the kc backend's QP allowance metric (KcParams::qpAllowance, kc::kAllowanceCap):
/// the correction that restores reproduction after the targets' floor falls on the controls near
/// a sample, not the farthest ones (a foot's weight on the back), and the drag area of `kcwarp-cli
/// stats` falls to about the LBC backend's; smaller ε is more local, and weakens a brush stroke's
/// effect more (docs/notes/measured-constants.md).
inline constexpr double kQpAllowance = 0.005;

/// Bind parameters of the kernel-coordinate backend ("kc").
struct KcParams {
  double sigma = 0.0;      ///< σ in pixels; ≤ 0 = automatic (3T/π, thesis 3.28, T measured).
  InitOptions init;        ///< W0: method, diffusion iterations (the locality length comes from `locality`).
  Method method = Method::QP;
  /// ε of the QP's allowance metric (OptimizeOptions::allowance; kQpAllowance), in [0, 1]; 0: the
  /// thesis's Euclidean QP (4.1). Bind and re-optimizations (painting) both use it. Sessions written
  /// before the option (no `params.qp_allowance`) read 0.
  double qpAllowance = kQpAllowance;
  InterpMode interp = InterpMode::Exact;
  /// `--linear-edges`: the field is made linear along every edge of the cage's loops (not the
  /// sticks) by the post-processing of the lines (thesis 5.3.3, makeLinearAlong), not only at the
  /// edge samples; deepens the negative lobes near the controls (docs/ARCHITECTURE.md). Sessions
  /// written before the option (no `params.linear_edges`) read false.
  bool linearEdges = false;
  /// How far the heat-linear targets reach (init.locality is not read: the bind sets it from this,
  /// app::locality). Screened targets make dragging one control move about its own part of the
  /// picture. The Spacings rule is not applied in binds with structure lines made linear through
  /// the samples (exactLines false): unscreened there. Sessions written before the option (no
  /// `params.locality_spacings`) read `params.locality` alone (pixels, < 0 automatic, 0 off).
  Locality locality;
  /// The floor of screened heat-linear targets (kc::floorTargets; kTargetFloor), in [0, kMaxTargetFloor): 0
  /// keeps the whole diffused tail. Applied where the targets are screened (`locality`). Sessions
  /// written before the option (no `params.target_floor`) read 0.
  double targetFloor = kTargetFloor;
  /// Bound the field's negative lobes inside the cage: the exterior rows next to the cage continue
  /// the inside across it (ExteriorContinuation), and sharp outside corners are sampled finer
  /// (app's sharp-corner seeds of the sizing field; exact interpolation only). No effect with
  /// linearEdges, whose post-processing sets the field next to the edges itself. Sessions written
  /// before the option (no `params.guard_lobes`) read false.
  bool guardLobes = true;
  /// Structure lines kept straight by the field's exact correction (LineCorrection: the weights
  /// along a line are linear to round-off, and the samples keep their optimized weights); false:
  /// the samples near the lines are post-processed (thesis 5.3.3: blend and linear fit). Sessions
  /// written before the option (no `params.exact_lines`) read false.
  bool exactLines = true;
  /// `--lift-lobes`, QP only: the field's lobes inside the cage deeper than LobeLiftOptions::trigger are lifted
  /// (kc::liftLobes: KernelField::lift, exact partition of unity and reproduction) at the bind, a
  /// method switch back to QP and a rebuild without stored coefficients; a brush stroke keeps the
  /// lift it finds. None with rigid regions, linearEdges or lines kept through the samples
  /// (exactLines false): the bumps would bend what they make; a rigidity stroke removes the lift.
  /// Sessions written before the option (no `params.lift_lobes`) read false. Off by default: the
  /// bumps move the weights along the cage's edges off their hat functions (the figure's edge
  /// linearity 0.066 → 0.104; docs/notes/measured-constants.md).
  bool liftLobes = false;
  /// `--lobe-bound`: the field's weights inside the cage stay ≥ −lobeBound (kc::LobeBound, applied
  /// on every evaluation; 0: none), in [0, kMaxLobeBound]. Only with the QP and exact interpolation,
  /// and not with linear edges or structure lines (app's installLobeBound says why). Sessions
  /// written before the option (no `params.lobe_bound`) read 0.
  double lobeBound = kLobeDepth;
};

/// Bind parameters of the local-barycentric-coordinates backend ("lbc"); the mesh spacing is
/// BindParams::spacing.
struct LbcParams {
  LbcTau tau = LbcTau::Square;     ///< φ_i = τ(D_i), LBC eq. 11.
  double tolerance = LbcOptions{}.tolerance;
  int maxIterations = LbcOptions{}.maxIterations;
  /// The certified optimality gap the solver stops at (LbcOptions::gapTolerance): the weights'
  /// objective is within this fraction of the optimum. 1%: weights within a few hundredths of the
  /// optimum's, without the long tail of ADMM iterations a 0.1% certificate takes on a tight cage.
  double gap = 0.01;
};

/// Parameters of one bind: the ones every backend shares, then each backend's own. Defaults are
/// what `kcwarp-cli bind` and the GUI use.
struct BindParams {
  std::string backend = "kc";
  double spacing = 6.0;    ///< h, pixels (sample spacing; a mesh backend's edge length).
  sampling::SamplerKind sampler = sampling::SamplerKind::BlueNoise;
  double margin = -1.0;    ///< Sampling margin around the image; < 0 = automatic.
  /// How far outside the cage the kc backend samples: a band around the cage
  /// (sampling::kExteriorBandSpacings·h), what the pinned, fixed and transparent outside modes
  /// need, or the whole frame, what `--outside deform` needs (exteriorFor; sessions written before
  /// the choice existed read Frame). A band session has no weights far outside the cage:
  /// sessionCapabilities() says so and warps refuse `deform` on it.
  sampling::ExteriorExtent exterior = sampling::ExteriorExtent::Band;
  std::uint64_t seed = 1;
  /// Graded sampling (blue noise): the spacing follows the cage's local feature size, from
  /// `spacing` away from narrow places down to what the narrowest place needs (featureSizing);
  /// false: one spacing everywhere (`--uniform-spacing`; sessions written before grading existed).
  bool graded = true;
  KcParams kc;             ///< Used when backend == "kc".
  LbcParams lbc;           ///< Used when backend == "lbc" (and by the kc backend's LBC targets).
  /// The parameters of backends that keep no struct here (BackendParameter without get/set), by
  /// "<block>.<key>"; a parameter missing from the map has its default.
  std::map<std::string, double, std::less<>> values;
};

/// BindParams{} with the whole frame sampled (exterior = Frame): the thesis's set-up, which the
/// paper reproductions, the benchmarks' fixed scenes and `--outside deform` use.
inline BindParams frameBindParams() {
  BindParams p;
  p.exterior = sampling::ExteriorExtent::Frame;
  return p;
}

// The names of InitMethod, Method, InterpMode, SamplerKind and LbcTau (kc/core/names.h), also as app::.
using kc::toString;

/// Seconds spent in each stage of a bind (saved with the session as its `timings` block).
struct BindTimings {
  double sampling = 0.0, assemble = 0.0, factor = 0.0, init = 0.0, optimize = 0.0, solve = 0.0, total = 0.0;
};

/// A backend's own account of a bind, beyond the stages every bind has (the LBC backend's ADMM
/// solve). Made by the backend's bind; written to the session's `reports.<block>` (block =
/// Backend::parameterBlock()) by toJson and read back by Backend::readReport; shown through
/// these functions by `kcwarp-cli bind`/`stats`/`demo` and the GUI, which never look inside.
class BackendReport {
 public:
  virtual ~BackendReport() = default;
  /// The vertices of a mesh backend's field (its samples are the mesh's vertices); 0: none.
  virtual Index meshVertices() const { return 0; }
  /// The solver's line of BindReport::summary(), e.g. "LBC on 1134 vertices, 2076 ADMM iterations, …".
  virtual std::string summary() const = 0;
  /// Failures a user must see, one line each (BindReport::problems()).
  virtual std::vector<std::string> problems() const { return {}; }
  /// The few words of the GUI's bind message, e.g. "1134 mesh vertices, 2076 iterations".
  virtual std::string brief() const = 0;
  /// What summary() leaves out (`kcwarp-cli stats` and `demo`): lines starting with `indent`,
  /// with the bind's parameters the solver ran with.
  virtual std::string details(const BindParams& params, const char* indent) const = 0;
  /// The session's `reports.<block>` (session = true) or `kcwarp-cli stats --json`'s
  /// `solver.<block>` (false) as a JSON object.
  virtual void toJson(nlohmann::json& out, bool session) const = 0;
};

/// What one bind did, and the last whole re-optimization since: each stage's report, its time and
/// the backend's own report. The session keeps it (Session::report) and saves the stages the user
/// must see as its `reports` block and the times as its `timings` block; factor, lines and
/// rigidity live in memory only.
struct BindReport {
  sampling::SamplingReport sampling;
  InitReport init;
  OptimizeReport optimize;
  InterpolatorReport factor;
  LinearityReport lines;    ///< Structure lines (thesis 5.3.3); empty without lines.
  RigidityReport rigidity;  ///< Rigid regions (thesis 5.4, docs/rigidity.md); empty without them.
  LobeLiftReport lift;      ///< The lobe lift (KcParams::liftLobes); empty without it.
  BindTimings timings;
  std::shared_ptr<const BackendReport> backend;  ///< Null for a backend without one (kc).

  /// backend->meshVertices(), 0 without a backend report.
  Index meshVertices() const { return backend ? backend->meshVertices() : 0; }
  /// True when some stage failed or fell back (the GUI's warning colour).
  bool anyProblem() const;
  /// One line per problem, e.g. "optimization: 3 samples not solved to optimality …"; empty when none.
  std::vector<std::string> problems() const;
  /// One line: "solver: …" (the backend's summary, else the per-sample optimization's) and the
  /// problems, or "no failures".
  std::string summary() const;
};

struct Session {
  Cage cage;
  BindParams params;
  double sigma = 0.0;          ///< σ actually used (kc); with a graded sampling, σ where h = params.spacing.
  /// The local spacing of a graded sampling (the session's `sizing` block), which the kernel's
  /// width follows (σ(x) = sigma · h(x) / params.spacing); null for a uniform one.
  std::shared_ptr<const SizingField> sizing;
  int imageWidth = 0, imageHeight = 0;
  SampleSet samples;
  /// Lines kept straight / parallel (thesis 5.3); their samples are samples.lines[k]. Rigid
  /// regions (structure.rigid) are where `rigidity` came from.
  Structure structure;
  /// Per-sample rigidity ρ ∈ [0, 1] (#S, or empty: none), thesis 5.4 / docs/rigidity.md: what the
  /// rigid regions give at bind and what a rigidity brush paints (app::setRigidity). W holds
  /// the weights with it applied.
  std::vector<double> rigidity;
  Weights W0;                  ///< Initial (target) weights, #S×m; empty when the backend has no targets.
  Weights W;                   ///< Optimized weights, #S×m.
  Pose pose;                   ///< Current pose (empty = rest).
  std::string image;           ///< Image path as written in the file (may be empty).
  /// The picture is the image turned as its Exif orientation says (loadImage's
  /// ImageOrientation::Upright), which is how it was shown when the cage was drawn; false: as
  /// stored (sessions written before kcwarp read the orientation, whose `image_upright` key is
  /// missing).
  bool imageUpright = true;
  /// The user's outside-the-cage choice, none when none was made: warps then use WarpMeshOptions'
  /// default (pinned). In the file: the kc::OutsideMode name, or no key.
  std::optional<OutsideMode> outside;
  /// Kernel coordinates on LBC targets (`--init lbc`, kc backend): the spacing of the LBC mesh the
  /// targets were solved on, which the warp mesh follows (warpMeshOptionsFor). Sessions written
  /// before the samples were made denser than that mesh read their sample spacing (their mesh was
  /// at it). 0: not such a session, or one built in memory: weightSpacing(params).
  double lbcMeshSpacing = 0.0;
  BindReport report;  ///< What the bind did (BindReport).
  /// The coordinate field: the only way to weights at points. Built by the backend (bind) or
  /// from the session file's field block; null before.
  std::unique_ptr<CoordinateField> field;

  /// True when the field can be evaluated.
  bool hasField() const { return field && field->ready(); }
  /// Some sample is rigid (rigidity ρ > 0 anywhere).
  bool hasRigidity() const {
    for (const double r : rigidity)
      if (r > 0.0) return true;
    return false;
  }
};

}  // namespace kc::app
