#pragma once
// Test support: GLPK's exact (rational) simplex as the reference for the per-sample ℓ1 problem
// (thesis 4.8).

#include <glpk.h>

#include <Eigen/Core>

#include "sample_problems.h"

namespace kc::test {

/// GLPK on min Σ(p_i + q_i) s.t. Σ a_i(p_i − q_i) = b − A w0, p, q ≥ 0, optionally with an
/// extra objective bound Σ(p + q) ≤ bound and a secondary objective dir·v (to probe the optimal
/// face). Returns v = p − q and the objective value; false when GLPK reports no optimum.
inline bool glpkSolve(const Problem& p, Eigen::VectorXd& v, double& objective, const Eigen::VectorXd* dir = nullptr,
               double bound = 0.0) {
  const int m = static_cast<int>(p.C.rows());
  const Eigen::Vector3d r = Eigen::Vector3d(p.x.x(), p.x.y(), 1.0) -
                            Eigen::Vector3d(p.C.col(0).dot(p.w0), p.C.col(1).dot(p.w0), p.w0.sum());
  glp_term_out(GLP_OFF);
  glp_prob* lp = glp_create_prob();
  glp_set_obj_dir(lp, GLP_MIN);
  glp_add_cols(lp, 2 * m);
  glp_add_rows(lp, dir ? 4 : 3);
  for (int k = 0; k < 3; ++k) glp_set_row_bnds(lp, k + 1, GLP_FX, r(k), r(k));
  if (dir) glp_set_row_bnds(lp, 4, GLP_UP, 0.0, bound);
  for (int i = 0; i < m; ++i) {
    for (int s = 0; s < 2; ++s) {
      const int col = 2 * i + s + 1;
      const double sign = s == 0 ? 1.0 : -1.0;
      glp_set_col_bnds(lp, col, GLP_LO, 0.0, 0.0);
      glp_set_obj_coef(lp, col, dir ? sign * (*dir)(i) : 1.0);
      int idx[5] = {0, 1, 2, 3, 4};
      double val[5] = {0.0, sign * p.C(i, 0), sign * p.C(i, 1), sign, 1.0};
      glp_set_mat_col(lp, col, dir ? 4 : 3, idx, val);
    }
  }
  glp_smcp parm;
  glp_init_smcp(&parm);
  glp_simplex(lp, &parm);
  glp_exact(lp, &parm);  // rational arithmetic from GLPK's basis: an exact reference
  const bool ok = glp_get_status(lp) == GLP_OPT;
  v.resize(m);
  objective = 0.0;
  for (int i = 0; i < m; ++i) {
    v(i) = glp_get_col_prim(lp, 2 * i + 1) - glp_get_col_prim(lp, 2 * i + 2);
    objective += glp_get_col_prim(lp, 2 * i + 1) + glp_get_col_prim(lp, 2 * i + 2);
  }
  glp_delete_prob(lp);
  return ok;
}

}  // namespace kc::test
