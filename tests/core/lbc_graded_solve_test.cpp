// The LBC solver on a graded mesh with a narrow place (a square with a 3 px slit): it stops
// certified within 0.1% of the optimum in a bounded number of iterations, with exact barycentric
// weights, and the controls across the slit weigh exactly 0 beside it.
#include <gtest/gtest.h>

#include <memory>

#include "kc/core/lbc/cage_mesh.h"
#include "kc/core/lbc/lbc_solver.h"
#include "kc/core/sizing.h"
#include "lbc_cages.h"

namespace kc {
namespace {

TEST(LbcGradedSolve, ASlitCageIsCertifiedWithinAThousandthInBoundedIterations) {
  const Cage cage = test::slitCage();
  const Points& C = cage.C;
  SizingOptions so;
  so.hMax = 10.0;
  so.featureSamples = so.narrowWidth = so.extraNarrowWidth = 1.0;  // the LBC backend's: one triangle across a narrow place
  so.fineGradation = so.gradation;                                 // and one gradation
  CageMeshOptions mo;
  mo.spacing = so.hMax;
  mo.sizing = std::make_shared<SizingField>(featureSizing(cage, {}, so));
  const CageMesh mesh = meshCageInterior(cage, mo);
  ASSERT_EQ(mesh.status, SolveStatus::Ok);

  const LbcSolver solver(mesh, LbcTau::Square);
  const LbcResult r = solver.solve();
  ASSERT_EQ(r.report.status, SolveStatus::Ok);
  // Certified: the returned objective within 0.1% of a lower bound on the optimum (weak duality).
  EXPECT_LE(r.report.lowerBound, r.report.objective);
  EXPECT_LE(r.report.objective - r.report.lowerBound, LbcOptions{}.gapTolerance * r.report.lowerBound);
  EXPECT_EQ(solver.objective(r.W), r.report.objective);
  // Measured 225 iterations (the same on 1 and 2 threads): the bound keeps the count from growing
  // unnoticed.
  EXPECT_LE(r.report.iterations, 300) << r.report.iterations;

  // Exact barycentric weights, ≥ 0.
  EXPECT_GE(r.W.minCoeff(), 0.0);
  for (Index v = 0; v < mesh.size(); ++v) {
    EXPECT_NEAR(r.W.row(v).sum(), 1.0, 1e-9);
    EXPECT_LE((r.W.row(v) * C - mesh.V.row(v)).norm(), 1e-9);
  }
  // Beside the slit's left wall, the right wall's controls (across the gap, 140–260 px round its
  // end) weigh nothing but what ADMM leaves of a zero at its tolerance (as in the app's narrow-cage
  // tests: ≤ 1e-5).
  int beside = 0;
  for (Index v = mesh.boundary; v < mesh.size(); ++v) {
    const Vec2 x = mesh.V.row(v);
    if (x.x() < 145.0 || x.x() > 148.5 || x.y() < 60.0 || x.y() > 120.0) continue;
    ++beside;
    EXPECT_LE(r.W(v, 3) + r.W(v, 4), 1e-5) << "vertex " << v << " at " << x.transpose();
  }
  EXPECT_GT(beside, 20);
}

}  // namespace
}  // namespace kc
