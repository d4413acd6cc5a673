#pragma once
/// Rigid regions in a bound session (thesis 5.4; docs/rigidity.md): the entry point a rigidity
/// brush calls after a stroke.

#include <exception>
#include <functional>
#include <span>
#include <vector>

#include "kc/core/solve.h"
#include "kc/app/session.h"
#include "kc/core/structure/rigidity.h"

namespace kc::app {

/// What setRigidity did.
struct RigidityUpdate {
  RigidityReport report;        ///< The rigidity QP's outcome (region, nodes, energies, solver).
  std::vector<Index> rows;      ///< Samples whose weights were re-derived: within (reach + 5)σ of the old or new ρ > 0.
  std::vector<Index> columns;   ///< Controls whose field columns changed (update a FieldSampler with these).
  double seconds = 0.0;
};

/// Sets the per-sample rigidity of a bound kernel session and re-solves only around it:
/// `rho` (#S entries, each in [0, 1]; 0 = not rigid) replaces session.rigidity; the samples
/// within (reach + 5)σ of a sample whose old or new ρ is positive get their unconstrained weights
/// back (the per-sample optimization from W0 with the session's method; lines re-applied when the
/// session has lines), then kc::makeRigid solves the rigidity QP (docs/rigidity.md) around the new
/// region, and the field's changed columns are re-solved. Weights farther away do not change.
/// session.structure.rigid (the polygons) is left as it is: the brush's ρ is what counts.
/// `progress` (optional) hears the stages ("restoring the unconstrained weights", "rigidity
/// solve", "field") with the share done, between steps of at most ~0.1 s on a 2,000-sample region;
/// when it returns false the session's weights, rigidity and field are put back and
/// kc::Cancelled is thrown.
/// Throws std::invalid_argument when the session is not a bound kernel session with target
/// weights (weights.initial), or rho has the wrong size or a value outside [0, 1].
RigidityUpdate setRigidity(Session& session, std::span<const double> rho, const StageProgress& progress = {});

/// The thesis's Fig 6.37 set-up on a five-pointed star cage of 10 points (tips at even indices,
/// like the bundled images/star): the rigid region is the inner part of the bottom-right leg
/// (tip 4 between inner points 3 and 5) — a triangle on the leg's base, 12% in from each end,
/// reaching 55% of the way to the tip — and the pose moves the tip 40 px toward the cage's
/// centroid. Used by `bench --rigid` and the tests. Throws std::invalid_argument for m ≠ 10.
struct StarLegSetup {
  Points polygon;  ///< 3×2.
  Pose pose;
  Vec2 centroid = Vec2::Zero();
};
StarLegSetup starLegSetup(const Cage& star);

/// How rigidly a region deforms (`kcwarp-cli bench --rigid`) at the points of a grid of spacing `step`
/// inside `polygon`: J the Jacobian of f(x) = Σ w_i(x) T_i x (3.44) for the pose, R its nearest
/// rotation (polar decomposition).
struct RigidityFigures {
  Index points = 0;
  double distortion = 0.0;    ///< Mean ‖J − R‖_F.
  double unity = 0.0;         ///< max |Σ_i w_i − 1|.
  double reproduction = 0.0;  ///< max |Σ_i w_i c_i − x| (pixels).
  double minWeight = 0.0;     ///< Smallest weight.
};
/// Measures the session's field over the polygon (≥ 3 points) for `pose` (empty: rest). Throws
/// std::invalid_argument without a field or when no grid point lies inside the polygon.
RigidityFigures measureRigidity(const Session& session, const Points& polygon, const Pose& pose, double step = 1.0);

}  // namespace kc::app
