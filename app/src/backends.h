#pragma once
// Private to kc::app: the backend instances behind backendFor().

#include <functional>

#include "kc/app/backend.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/lbc_solver.h"
#include "kc/core/structure/linear_along.h"

namespace kc::app {

/// Kernel coordinates (kc_backend.cpp).
const Backend& kcBackend();
/// Local barycentric coordinates on a mesh of the cage interior (lbc_backend.cpp).
const Backend& lbcBackend();

/// The LBC mesh of a cage and its solved weights.
struct LbcBind {
  CageMesh mesh;
  LbcResult result;  ///< Converged (else solveLbcForBind threw).
  double meshSeconds = 0.0;
};

/// Meshes the cage at params.spacing and solves LBC with params.lbc, reporting stages through
/// `step` ("mesh", "geodesics", "LBC iterations"; step throws to cancel). Throws
/// std::invalid_argument with advice for a mesh above kcwarp's vertex limit, a failed
/// factorization or no convergence within the iteration cap. Shared by the "lbc" backend and the
/// kc backend's `--init lbc`.
/// Structure lines in a kernel session (thesis 5.3.3), after the per-sample optimization: couples
/// the base points (the line ends) of parallel groups (5.11), sets the intermediate line samples'
/// weights linear between them (5.6), re-solves `field` and post-processes the neighbouring
/// samples so that the field is linear along each whole line (makeLinearAlong). Does nothing
/// without lines. Returns the post-processing's report.
LinearityReport applyLines(Session& s, KernelField& field);

LbcBind solveLbcForBind(const Cage& cage, const BindParams& params, const std::function<void(const char*, double)>& step);

}  // namespace kc::app
