#pragma once
// Private to kc::app: the backend instances behind backendFor().

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kc/app/backend.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/lbc_solver.h"
#include "kc/core/structure/linear_along.h"
#include "kc/core/structure/rigidity.h"
#include "kc/core/weights/exterior_continuation.h"

namespace kc::app {

/// Kernel coordinates (kc_backend.cpp).
const Backend& kcBackend();
/// Its parameters (kc_parameters.cpp): KcParams described, keys at the top of the session's params.
const std::vector<BackendParameter>& kcParameters();
/// Its parameters that are not `stored`: `sigma_auto` (σ itself is the session's `sigma`, the σ
/// used) and the locality rule (`locality` in pixels, < 0 automatic; `locality_spacings`, which
/// wins when > 0; both 0 or absent: off). readKcParameters needs s.sigma read before.
void writeKcParameters(const Session& s, nlohmann::json& params);
void readKcParameters(const nlohmann::json& params, Session& s, const std::string& where);
/// Local barycentric coordinates on a mesh of the cage interior (lbc_backend.cpp).
const Backend& lbcBackend();

/// The LBC mesh of a cage and its solved weights.
struct LbcBind {
  CageMesh mesh;
  LbcResult result;  ///< Converged (else solveLbcForBind threw).
  double meshSeconds = 0.0;
  std::shared_ptr<const SizingField> sizing;  ///< The mesh's sizing field (bindSizing), or null: uniform.
};

/// Meshes the cage at params.spacing, graded by bindSizing(cage, no structure, params) where the
/// cage has narrow places, and solves LBC with params.lbc, reporting stages through
/// `step` ("mesh", "geodesics", "LBC iterations"; step throws to cancel). Throws
/// std::invalid_argument with advice for a mesh above kcwarp's vertex limit, a failed
/// factorization or no convergence within the iteration cap. Shared by the "lbc" backend and the
/// kc backend's `--init lbc`.
LbcBind solveLbcForBind(const Cage& cage, const BindParams& params, const std::function<void(const char*, double)>& step);

/// Structure lines and cage edges in a kernel session (thesis 5.3.3), after the per-sample
/// optimization: with params.kc.linearEdges, first post-processes the samples near each edge of the
/// cage's loops so that the field is linear along it from one control's Lagrange weights to the
/// other's (4.7). Then, with params.kc.exactLines, installs the field's line correction
/// (installLineCorrection; report: the largest L1 misfit of the weights from linear along the lines
/// before and after it; the samples keep their weights). Without it (sampled lines), couples the base
/// points (the line ends) of parallel groups (5.11), blends the neighbourhoods toward the lines
/// (kc::blendLineNeighbourhoods), sets the intermediate line samples' weights linear between them
/// (5.6), re-solves `field` and post-processes the neighbouring samples so that the field is linear
/// along each whole line (makeLinearAlong). `field` must hold s.W on entry (the weights before the
/// lines). Does nothing without lines and linear edges. Returns the post-processing's report (lines
/// and edges together).
LinearityReport applyLines(Session& s, KernelField& field);

/// Sets (params.kc.exactLines and lines) or removes the line correction of a kernel session's
/// field: kc::LineCorrection for s.cage, s.structure.lines, their contacts and s.sigma, with the
/// structure's rigid polygons (strength > 0) as barriers.
void installLineCorrection(const Session& s, KernelField& field);

/// Rigid regions in a kernel session (docs/rigidity.md), after the lines: kc::makeRigid with
/// s.rigidity, holding controls and line samples. Does nothing without a positive ρ.
/// Throws std::invalid_argument when s.rigidity does not have one entry per sample. `progress`
/// (optional) is the QP's (RigidityQpOptions::progress: false cancels with kc::Cancelled).
RigidityReport applyRigidity(Session& s, KernelField& field, const Progress& progress = {});
/// Gives rows `rows` of s.W their unconstrained weights again (per-sample optimization from W0
/// with the session's method; lines re-applied when there are lines) and re-solves the field's
/// changed columns, which are appended to `columns`.
void restoreUnconstrained(Session& s, KernelField& field, std::span<const Index> rows, std::vector<Index>& columns);

/// The options of bindSizing's sizing field for a bind with `params` (hMax = params.spacing).
SizingOptions bindSizingOptions(const BindParams& params);
/// The exterior continuation of a kc session's bind (KcParams::guardLobes) over its samples; empty
/// when the option is off, or with linearEdges, whose post-processing of the rows next to the
/// edges sets the field there itself. Its construction fits every exterior row near the cage:
/// build it once per bind or re-optimization and pass it on.
ExteriorContinuation continuationFor(const Session& s);

/// rederivedRows (pipeline.h) with the session's continuation already built.
std::vector<Index> rederivedRows(const Session& s, const ExteriorContinuation& continuation, std::span<const Index> rows);

/// Per-sample optimization of rows `rows` (sorted; all when empty) of s.W from s.W0 with `method`
/// (WeightOptimizer), then `continuation` (continuationFor(s)) applied to the continued rows among
/// them (all of them for an empty `rows`). Pass rows from rederivedRows so that the continued rows
/// reading a re-optimized row are among them.
OptimizeReport optimizeRows(Session& s, Method method, std::span<const Index> rows, const ExteriorContinuation& continuation);

/// The field's lobe lift for the session's parameters (KcParams::liftLobes): removed, then found
/// anew with the QP (kc::liftLobes); none for QEC and L1, nor with rigidity, rigid regions, linear
/// edges or lines kept through the samples.
LobeLiftReport liftFieldLobes(const Session& s, KernelField& field);

/// The field's lobe bound for the session's parameters (KcParams::lobeBound, kc::LobeBound, fading
/// outside the cage over σ, in the QP's allowance metric): set with the QP and exact interpolation
/// on a cage with an interior, removed otherwise: QEC and L1, whose weights may be negative by
/// design; the thesis's interpolation, whose partition of unity is approximate (a projection,
/// exact, would make a jump where it starts); linear edges and structure lines, whose weights are
/// made linear along them (a projection would bend them).
void installLobeBound(const Session& s, CoordinateField& field);

}  // namespace kc::app
