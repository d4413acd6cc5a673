#pragma once
/// The bind pipeline: cage → (backend) → coordinate field (ARCHITECTURE.md data flow).

#include <functional>
#include <optional>
#include <string>
#include <span>
#include <vector>

#include "kc/app/backend.h"
#include "kc/app/limits.h"
#include "kc/app/session.h"
#include "kc/core/solve.h"

namespace kc::app {

/// Automatic sampling margin in `thesis` interpolation mode, in sample spacings (the exact mode
/// uses the sampler's default of about 3h): on a cage that spans its image, 10h brings the
/// partition-of-unity error from ~1e-2 at 3h to ~1e-3 (docs/notes/measured-constants.md).
inline constexpr double kThesisMarginSpacings = 10.0;

/// The sampler's options for a bind of width×height with `p` (what the kc backend samples and
/// the cost estimate counts): spacing, sampler, seed, the margin — the user's, else automatic —
/// and the exterior extent; a band is max(kExteriorBandSpacings·h, 2·automaticMeshSpacing) wide.
sampling::SamplingOptions samplingOptions(int width, int height, const BindParams& p);

/// True when a bind with `params` samples or meshes graded: params.graded and, for a backend that
/// samples the picture (kc), blue noise; the LBC backend grades its mesh of the cage interior.
/// Such a bind refuses no narrow place of the cage or its lines.
bool gradedSampling(const BindParams& params);
/// True when a bind with `params` keeps structure lines straight by the field's exact correction
/// (KcParams::exactLines on a backend that samples the picture): the lines are then not part of the
/// sampling (no line samples, no refinement around them), and only lines that leave the cage or
/// overlap another are refused (validateLines' graded rules).
bool exactLines(const BindParams& params);
/// The parameters a bind of `cage` with `structure` really uses (bind(), the Bind panel's planned
/// spacing and the cost estimate all go through it): `params`, with `graded` off where the bind
/// samples uniformly although a graded sampling was asked for — structure lines on the kc backend
/// (blue noise) whose cage and lines the uniform rules accept at params.spacing (no cage feature
/// narrower than kMinFeatureSpacings·h, lines at least h from the cage and from each other, no
/// crossing, each at least kMinLineSpacings·h long): there the weights beside a line ring less (a
/// long line near the star's edge: lobe −0.14 graded, within −0.1 uniform). Crossing lines, lines
/// near the cage and narrow cages keep the graded sampling; without lines, or on a backend without
/// samples outside the cage (LBC), `params` as given. The sampling of the result is graded when
/// gradedSampling(result), with the sizing field bindSizing(cage, structure, result); its kernel
/// width follows SizingForm::Smooth with lines, SizingForm::Min without. Throws
/// std::invalid_argument for an unknown backend. With exactLines(params), `params` as given.
BindParams effectiveBindParams(const Cage& cage, const Structure& structure, const BindParams& params);
/// The sizing field of a graded bind (gradedSampling): featureSizing of the cage, the structure
/// lines (not with exactLines) and the rigid polygons' sides with hMax = params.spacing and hMin = kMinSpacing (the LBC
/// backend's mesh with k = n = 1, one triangle across a narrow place: SizingOptions);
/// null for a uniform bind or a cage without a narrow place (h ≡ spacing). `params` are the
/// bind's own (effectiveBindParams): with the requested ones, lines the uniform rules accept
/// would get a sizing field the bind does not use.
std::shared_ptr<const SizingField> bindSizing(const Cage& cage, const Structure& structure, const BindParams& params);

/// What a bind would need, estimated from its inputs before anything is sampled or allocated.
struct BindCost {
  double samples = 0.0;         ///< #S: sampler's estimate (domain area / h², plus the cage's perimeter / h).
  double controls = 0.0;        ///< m.
  double kernelNonZeros = 0.0;  ///< nnz(K): #S × the samples within the cut-off 5σ of one sample.
  double bytes = 0.0;           ///< Peak memory: dense #S×m weight matrices plus K and its factor.
};

/// The estimate for a bind of `cage` over width×height with `params` (σ automatic: 3h/π).
BindCost estimateBindCost(const Cage& cage, int width, int height, const BindParams& params);
/// The same for a bind with `structure`: with the parameters it really uses (effectiveBindParams)
/// and a graded sampling's refinement along the lines and rigid polygons (bindSizing).
BindCost estimateBindCost(const Cage& cage, const Structure& structure, int width, int height, const BindParams& params);

/// Sample budget of the automatic spacing, counted over the cage's bounding box and its exterior
/// band (sampling::ExteriorExtent::Band). Chosen so that a cage's bind costs about the same at
/// any picture size (docs/notes/big-pictures.md).
inline constexpr double kAutoSpacingSamples = 2500.0;

/// Vertex budget of the LBC backend's automatic mesh spacing (estimateMeshVertices of the uniform
/// mesh of the cage interior; a graded mesh adds what its narrow places need).
inline constexpr double kAutoLbcVertices = 1200.0;

/// Kernel coordinates on LBC targets (`--init lbc`) sample the cage at this fraction of the LBC
/// mesh's spacing: the LBC weights are solved on a mesh of spacing h / kLbcTargetSampling and the
/// kernel samples lie h apart (h = BindParams::spacing). A kernel field rings where it interpolates
/// targets that fall to exactly 0 with a kink, and the ring reaches about a sample spacing past
/// each weight's support; sampling twice as densely as the mesh halves that halo, while the LBC
/// solve, the bind's slowest stage, keeps its cost (docs/notes/lbc-backend.md, "KC on LBC targets").
inline constexpr double kLbcTargetSampling = 0.5;

/// The spacing of the weights' detail, which the warp mesh follows (automaticMeshSpacing): the
/// sample spacing, or with `--init lbc` (kc backend) the LBC mesh's, spacing / kLbcTargetSampling
/// (the samples there are denser than the weights' detail; a warp mesh as fine as they are only
/// costs more per pose).
double weightSpacing(const BindParams& params);

/// The exterior a bind needs for an outside mode: the whole frame for deform (the field's own
/// weights everywhere), the band around the cage for the others.
sampling::ExteriorExtent exteriorFor(OutsideMode outside);

/// The spacing a bind uses when the user gives none, from the cage rather than the pixels:
/// `params.spacing` (the 6 px default, the floor) while the estimated sample count of a band
/// bind (estimateBindCost with ExteriorExtent::Band: the cage's bounding box grown by
/// kExteriorBandSpacings·h, ~ its area / h² + perimeter / h) stays within `budget`, else the
/// h ≥ params.spacing whose estimate is about `budget`, found by h ← h·√(#S(h)/budget) (three
/// steps) and rounded up to 0.01 px. The count does not depend on the cage's scale: the same cage
/// 10× larger gets 10× the spacing. A whole-frame bind (params.exterior) uses the same h, grown by
/// 5% steps while it exceeds kcwarp's limits. Where the cage has a feature narrower than
/// kNarrowFeatureSpacings·h (narrowestGap), h shrinks to narrowest/kNarrowFeatureSpacings (not
/// below params.spacing), over the budget but never past kcwarp's limits (checkBindCost); a graded
/// bind (gradedSampling) keeps h and refines its narrow places itself. The LBC backend meshes the
/// cage interior: its h ≥ params.spacing is the spacing whose uniform mesh has about
/// kAutoLbcVertices vertices (estimateMeshVertices; `budget` counts samples and does not apply),
/// rounded up to 0.01 px. With `--init lbc`
/// (kc backend) it is kLbcTargetSampling times the spacing of the same bind with heat-linear
/// targets (which the LBC mesh then uses), grown by 5% steps while it exceeds kcwarp's limits.
double automaticSpacing(const Cage& cage, int width, int height, const BindParams& params, double budget = kAutoSpacingSamples);

/// "" when every cage feature is at least kNarrowFeatureSpacings·spacing wide (or narrower than
/// kMinFeatureSpacings·spacing, which bind() refuses), else a warning naming the narrowest place
/// (points or edges), its width, and the spacing that resolves it.
std::string narrowFeatureWarning(const Cage& cage, double spacing);
/// The same for a bind with `params`: "" when its sampling is graded (it refines narrow places).
std::string narrowFeatureWarning(const Cage& cage, double spacing, const BindParams& params);

/// The largest of cost / limit over kcwarp's bind limits (kMaxBindSamples, kMaxKernelNonZeros,
/// kMaxBindBytes): ≤ 1 when the bind fits.
double bindLimitFactor(const BindCost& cost);

/// Throws std::invalid_argument when `cost` exceeds kcwarp's limits (kMaxBindSamples,
/// kMaxKernelNonZeros, kMaxBindBytes), saying what the bind would need and the spacing (or σ)
/// that would fit.
void checkBindCost(const BindCost& cost, const BindParams& params);

/// Estimate of the automatic σ before sampling: 3T/π (thesis 3.28) with T = h. bind() itself
/// uses the measured mean nearest-neighbour spacing of the samples (sampling::suggestSigma).
double automaticSigma(double spacing);

/// Binds a cage over an image of width×height pixels with the backend params.backend; what the
/// bind did is the session's `report` (with its total time). Throws
/// InputError for bad input (invalid cage, bad parameters, unknown backend, too many samples, a
/// kernel matrix that cannot be factorized with these σ and spacing, with the report's advice).
Session bind(const Cage& cage, int width, int height, const BindParams& params, const StageProgress& progress = {});
/// The same with structure lines kept straight and parallel (thesis 5.3): InputError when the
/// lines do not fit the cage (checkStructure) or the backend has no `lines` capability.
Session bind(const Cage& cage, const Structure& structure, int width, int height, const BindParams& params,
             const StageProgress& progress = {});

/// Re-optimizes rows `subset` of session.W (all when empty) from session.W0 with `method`, then
/// updates the coordinate field's columns that changed (all of them when the subset is empty).
/// `changedColumns`, when given, receives those columns. Returns the optimizer's report. Throws
/// std::invalid_argument when the session's backend cannot re-optimize (sessionCapabilities).
OptimizeReport reoptimize(Session& session, Method method, std::span<const Index> subset = {},
                          std::vector<Index>* changedColumns = nullptr);

/// The locality length (pixels) of a kc bind's screened targets under the Spacings rule, S spacings:
/// ℓ = max(S·spacing, D/4), D the cage's depth, the largest distance from a point inside the cage
/// to its edges (on a grid of step spacing/2, at most ~20,000 points). The targets decay like
/// exp(−d/ℓ) from the cage inwards; where the deepest point keeps much less than e^−4 ≈ 2% of the
/// heat that leaves the cage, the discretized diffusion's error there is of the targets' size and
/// the optimizer turns it into lobes (docs/notes/measured-constants.md). A cage with no inside (open
/// sticks) has D = 0.
double localityLength(const Cage& cage, double spacing, double spacings);

/// The locality length (pixels) a kc bind with `params` screens its heat-linear targets with
/// (kc::InitOptions::locality), or none (unscreened): params.kc.locality's rule resolved on `cage`
/// at params.spacing, the spacing the bind samples at. `sampledLines`: the bind has structure lines
/// made linear through the samples (params.kc.exactLines false), where the Spacings rule is off.
/// Throws std::invalid_argument for a Spacings or Pixels value that is not finite and > 0.
std::optional<double> locality(const Cage& cage, const BindParams& params, bool sampledLines = false);

/// The rows of session.W a re-optimization of `rows` re-derives (sorted): `rows`, and with
/// params.kc.guardLobes the continued exterior rows next to the cage (ExteriorContinuation) that
/// read one of them around their mirror point or are one of them. Painting re-optimizes these.
std::vector<Index> rederivedRows(const Session& session, std::span<const Index> rows);

/// Rebuilds session.field from what a session file holds (after loading it), through its backend.
void refreshField(Session& session);

/// Frees what only further solves of session.field need — the kernel factorization, the largest
/// allocation a bind keeps (e.g. 215 MB of its 250 MB at 60,000 samples) — for a caller that only
/// saves or evaluates the session. The field still evaluates; its next update() (a paint stroke, a
/// method switch) factorizes again first, which costs about what the bind's factorization did.
void releaseFactorization(Session& session);

}  // namespace kc::app
