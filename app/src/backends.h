#pragma once
// Private to kc::app: the backend instances behind backendFor().

#include <functional>

#include "kc/app/backend.h"
#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/lbc_solver.h"

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
LbcBind solveLbcForBind(const Cage& cage, const BindParams& params, const std::function<void(const char*, double)>& step);

}  // namespace kc::app
