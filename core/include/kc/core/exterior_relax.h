#pragma once
/// The pinned outside mode's fold repair (exterior_untangle.h) relaxes its region after every
/// continuation step and once more at the end. Without it the background is squeezed into slivers
/// (between an arm raised towards the head and the head, say), which a picture drawn on them shows
/// as a crumpled patch, and the next step has no room to move. The relaxation lowers the symmetric Dirichlet energy of the region's stars,
///     E = Σ_t A_t (‖J_t‖²_F + ‖J_t⁻¹‖²_F),
/// which is smallest for rotations and grows without bound as a triangle degenerates (Smith and
/// Schaefer 2015, "Bijective parameterization with free boundaries"), so the squeeze spreads
/// evenly over the region instead of collapsing a few triangles. Gauss–Seidel over the region's
/// vertices: a Newton step of the vertex's star energy (2×2 Hessian from differences of the
/// exact gradient; the gradient when that is not positive definite), shortened until the energy
/// decreases, no star triangle flips and a border vertex is put back on the border line when it would cross it inward. So
/// the relaxation never folds a triangle and never raises the energy.

#include <vector>

#include "kc/core/exterior_untangle.h"
#include "kc/core/types.h"

namespace kc {

struct ExteriorRelaxReport {
  int sweeps = 0;
  double energyBefore = 0.0, energyAfter = 0.0;  ///< Σ over the region's stars' triangles (each once).
  double minJacobianBefore = 0.0, minJacobianAfter = 0.0;  ///< Over those triangles.
};

/// Relaxes the vertices `region` (free vertices of `topology`) of P (#V + ghosts rows, as in the
/// repair: ghost rows fixed) by at most `sweeps` Gauss–Seidel sweeps (fewer once a sweep lowers the
/// energy by less than 5e-4 of it). restX: rest positions of the same rows; triangles[0..nt) the
/// exterior triangles, then topology.ghosts. Vertices whose star has a triangle with det J ≤ 0
/// are left where they are.
ExteriorRelaxReport relaxExteriorRegion(const Points& restX, Points& P, const Triangles& triangles, Index nt,
                                        const ExteriorRepairTopology& topology, const std::vector<int>& region, int sweeps);

}  // namespace kc
