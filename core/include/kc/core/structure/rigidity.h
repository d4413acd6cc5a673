#pragma once
/// Rigid regions (thesis 5.4, QP 5.35; the formulation for the exact interpolation and its
/// derivation: docs/rigidity.md). The user paints a per-sample rigidity ρ ∈ [0, 1]; the kernel
/// coefficients of the samples near the painted ones change so that the weights' gradients over
/// the region shrink, while partition of unity and reproduction stay exact everywhere and the
/// weights farther than (reach + 5)σ from the region do not change at all.

#include <span>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/field/kernel_field.h"
#include "kc/core/structure/rigidity_qp.h"
#include "kc/core/types.h"

namespace kc {

/// A rigid region given as a polygon (pixels, any orientation, ≥ 3 points) and its strength s ∈ [0, 1].
struct RigidRegion {
  Points polygon;
  double strength = 1.0;
};

/// Checks rigid regions against the cage. Throws std::invalid_argument whose message begins with
/// "rigid[k]" for the first bad region: fewer than 3 points, a coordinate or the strength not
/// finite, strength outside [0, 1], zero area, a self-intersecting polygon, a vertex outside the
/// closed cage or a polygon edge crossing a cage edge. Open cages (no interior) get no regions.
void validateRigidRegions(const Cage& cage, std::span<const RigidRegion> regions);

/// True when p lies inside the polygon (even-odd rule; points on the boundary count as inside).
bool insidePolygon(const Points& polygon, const Vec2& p);

/// Area centroid of the closed polygon P (n×2, n ≥ 3, non-zero area).
Vec2 polygonCentroid(const Points& P);

/// Per-sample rigidity ρ (#S) of regions: ρ_i = the largest strength of a region containing x_i
/// (0 outside every region). X #S×2.
std::vector<double> rigidityOfRegions(const Points& X, std::span<const RigidRegion> regions);

struct RigidityOptions {
  double reach = 2.0;          ///< Nodes: samples within reach·σ of a sample with ρ > 0 (the change's local part reaches (reach + 5)σ; see docs/rigidity.md).
  double rigidityWeight = 1000.0; ///< κ: the rigidity term's weight against the fidelity term (docs/rigidity.md).
  double quadratureStep = 0.5;  ///< The rigidity energy is evaluated on a grid of this spacing (·σ) over the painted region.
  bool boundNodes = false;     ///< Non-negativity (5.35d) at the nodes too, not only at the painted samples (thesis 5.35d: the region).
  double activeWeight = 1e-3;  ///< Controls whose weights at every node are ≤ this keep their weights.
  RigidityQpOptions solver;
};

struct RigidityReport {
  Index region = 0;          ///< Samples with ρ > 0.
  Index nodes = 0;           ///< Samples whose kernel coefficients may change.
  Index controls = 0;        ///< Controls whose weights may change (active).
  std::vector<Index> columns;  ///< Those controls' indices: the field columns re-solved (empty when nothing changed).
  Index held = 0;            ///< Held samples (controls, cage-edge and line samples) whose weights are kept.
  Index changedRows = 0;     ///< Samples whose data weights changed.
  double energyBefore = 0.0; ///< Σ_i ρ_i σ² ‖∇w(x_i)‖²_F over the region's samples, before.
  double energyAfter = 0.0;  ///< The same after.
  double minWeight = 0.0;    ///< Smallest changed weight at a constrained sample (region and nodes), after.
  Index projectedRows = 0;   ///< Constrained samples whose new weights missed a bound and were projected onto it (partition of unity and reproduction kept).
  double projectionChange = 0.0;  ///< The largest weight change that projection made.
  RigidityQpReport solver;
  double seconds = 0.0;
};

/// Makes the weights of `field` rigid over the painted samples (docs/rigidity.md). With
/// I = {i : ρ_i > 0}, nodes N = samples within reach·σ of I, changed samples Ch = samples within
/// θ (the kernel's cut-off) of N, solves for ΔU (N×m) the QP
///   min  κ Σ_{q∈Q} ρ_q σ² ‖∇w(x_q) + ∇ΔW(x_q)‖²_F + Σ_{i∈Ch} (1 − ρ_i) ‖ΔW_i‖²      (5.12, 5.35a)
///   s.t. ΔU [1 C] = 0                (each row: partition of unity and reproduction, exact)
///        ΔW_h = 0 at held samples h (keep[h] ≠ 0: controls and line samples)
///        W_i + ΔW_i ≥ min(W_i, 0) at I ∪ N (I only when !boundNodes)   (5.35d)
///        ΔU[:, c] = 0 for controls c inactive at the nodes (weights ≤ activeWeight)
/// where Q is a grid of spacing quadratureStep·σ over the painted region (ρ_q = ρ of the nearest
/// sample, scaled so that Σ_q ρ_q = Σ_{i∈I} ρ_i), ΔW = K(·, N) ΔU and ∇ΔW(x) = ∂E/∂x, ∂E/∂y (the
/// field's gradient operators) times ΔU;
/// then W += K(Ch, N) ΔU (W #S×m, the field's data weights; each bounded row that misses its bound
/// by the solver's tolerance projected onto it, keeping its partition of unity and reproduction:
/// docs/rigidity.md, "Large regions") and the field is re-solved in the
/// active columns: it interpolates the new W (in exact mode the coefficients become U + ΔU
/// − K⁻¹P b, B + b with b = (PᵀK⁻¹P)⁻¹PᵀΔU, a small global term; plain mode
/// U + ΔU; docs/rigidity.md). `rho` and `keep`
/// have #S entries, ρ ∈ [0, 1]; C m×2 the controls. Does nothing when no ρ is positive.
RigidityReport makeRigid(KernelField& field, const Points& C, std::span<const double> rho, const std::vector<char>& keep,
                         Weights& W, const RigidityOptions& options = {});

/// The samples whose weights makeRigid may change for this ρ: within (reach·σ + θ) of a sample
/// with ρ > 0 (sorted indices). For re-solving after ρ changed: the rows to restore first.
std::vector<Index> rigidityZone(const KernelField& field, std::span<const double> rho, const RigidityOptions& options = {});

}  // namespace kc
