#include "kc/core/weights/heat_diffusion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/metrics.h"
#include "kc/core/parallel.h"
#include "point_problems.h"

namespace kc {
namespace {

/// Hand-made sampling: controls, edge samples at spacing ≈ h, a grid of spacing h inside the cage
/// (and, when margin > 0, outside it up to `margin`), keeping grid points ≥ h/2 from the cage.
SampleSet sampleCage(const Cage& cage, double h, double margin) {
  const Index m = cage.size();
  std::vector<Vec2> pts;
  std::vector<SampleKind> kinds;
  std::vector<std::array<int, 2>> ends;
  for (Index i = 0; i < m; ++i) {
    pts.emplace_back(cage.C.row(i));
    kinds.push_back(SampleKind::Control);
    ends.push_back({-1, -1});
  }
  for (const auto& [k, l] : cage.edges) {
    const Vec2 a = cage.C.row(k), b = cage.C.row(l);
    const int segments = std::max(1, static_cast<int>(std::round((b - a).norm() / h)));
    for (int s = 1; s < segments; ++s) {
      pts.push_back(a + (b - a) * (static_cast<double>(s) / segments));
      kinds.push_back(SampleKind::Edge);
      ends.push_back({k, l});
    }
  }
  const Vec2 lo = cage.C.colwise().minCoeff().transpose().array() - margin;
  const Vec2 hi = cage.C.colwise().maxCoeff().transpose().array() + margin;
  for (double y = lo.y() + 0.5 * h; y < hi.y(); y += h)
    for (double x = lo.x() + 0.5 * h; x < hi.x(); x += h) {
      const Vec2 p(x, y);
      if (distanceToCage(cage, p) < 0.5 * h) continue;
      const bool inside = insideCage(cage, p);
      if (!inside && (margin <= 0.0)) continue;
      pts.push_back(p);
      kinds.push_back(inside ? SampleKind::Interior : SampleKind::Exterior);
      ends.push_back({-1, -1});
    }
  SampleSet S;
  S.X.resize(static_cast<Index>(pts.size()), 2);
  S.edge.resize(static_cast<Index>(pts.size()), 2);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    S.X.row(static_cast<Index>(i)) = pts[i].transpose();
    S.edge.row(static_cast<Index>(i)) << ends[i][0], ends[i][1];
  }
  S.kind = kinds;
  return S;
}

/// A side×side square with controls at its corners and edge midpoints (counter-clockwise from 0, 0).
Cage squareWithMidpoints(double side) {
  const double a = side / 2;
  Points C(8, 2);
  C << 0, 0, a, 0, side, 0, side, a, side, side, a, side, 0, side, 0, a;
  return Cage::polygon(C);
}

using test::kernelFor;

/// U-shaped cage: two arms separated by a notch 3 units wide (narrower than the kernel's reach).
Cage uCage() {
  Points C(8, 2);
  C << 0, 0, 100, 0, 100, 60, 51.5, 60, 51.5, 10, 48.5, 10, 48.5, 60, 0, 60;
  return Cage::polygon(C);
}

/// The same control points with no edges: nothing is ever "crossed" (naive diffusion).
Cage withoutEdges(const Cage& cage) {
  Cage naive = cage;
  naive.closed = false;
  naive.edges.clear();
  return naive;
}

/// Largest weight of control `c` on interior samples of the right arm next to the notch.
double acrossNotch(const SampleSet& S, const Weights& W, int c) {
  double worst = 0.0;
  for (Index j = 0; j < S.size(); ++j)
    if (S.kind[static_cast<std::size_t>(j)] == SampleKind::Interior && S.X(j, 0) > 51.5 && S.X(j, 0) < 57.0 &&
        S.X(j, 1) > 35.0)
      worst = std::max(worst, std::abs(W(j, c)));
  return worst;
}

TEST(HeatDiffusionSlow, NeverLeaksAcrossTheCage) {
  const Cage cage = uCage();
  const double h = 1.5;
  const SampleSet S = sampleCage(cage, h, 0.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(h));
  // Control 6 = (48.5, 60): top of the left arm, right at the notch.
  for (const auto& [method, iterations] : {std::pair{InitMethod::HeatLinear, 0}, std::pair{InitMethod::HeatLinear, 200},
                                           std::pair{InitMethod::HeatImpulse, 50}}) {
    InitOptions opt;
    opt.method = method;
    opt.iterations = iterations;
    const Weights W = initialWeights(S, cage, K, opt);
    const Weights Wnaive = initialWeights(S, withoutEdges(cage), K, opt);
    const double shaped = acrossNotch(S, W, 6), naive = acrossNotch(S, Wnaive, 6);
    EXPECT_LT(shaped, 1e-3) << "iterations " << iterations;  // heat must go around the U (~100 units)
    EXPECT_GT(naive, 20 * std::max(shaped, 1e-6)) << "the unrestricted reference should leak";
  }
}

TEST(HeatDiffusion, ControlsAndEdgesKeepTheirFixedWeights) {
  const Cage cage = uCage();
  const SampleSet S = sampleCage(cage, 3.0, 4.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(3.0));
  const Weights W = initialWeights(S, cage, K, InitOptions{});
  const Index m = cage.size();
  EXPECT_EQ(lagrangeError(W.topRows(m)), 0.0);
  std::vector<Index> rows;
  std::vector<std::array<int, 2>> ends;
  for (Index j = 0; j < S.size(); ++j)
    if (S.kind[static_cast<std::size_t>(j)] == SampleKind::Edge) {
      rows.push_back(j);
      ends.push_back({S.edge(j, 0), S.edge(j, 1)});
    }
  ASSERT_FALSE(rows.empty());
  EXPECT_LE(edgeLinearityError(W(rows, Eigen::all), cage.C, S.X(rows, Eigen::all), ends), 1e-14);
  InitOptions lbc;
  lbc.method = InitMethod::Lbc;  // solved on a mesh by the kc backend, never here
  EXPECT_THROW(initialWeights(S, cage, K, lbc), std::invalid_argument);
}

TEST(HeatDiffusion, SteadyStateIsANonNegativePartitionOfUnity) {
  // (D_FF − K_FF) is an M-matrix and the fixed rows sum to 1: the solution does too, and lies in [0, 1].
  const Cage cage = uCage();
  const SampleSet S = sampleCage(cage, 3.0, 6.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(3.0));
  InitReport rep;
  const Weights W = initialWeights(S, cage, K, InitOptions{}, &rep);
  EXPECT_TRUE(rep.steadyState);
  EXPECT_EQ(rep.fallbackSamples, 0);
  EXPECT_LE(partitionOfUnityError(W), 1e-10);
  EXPECT_GE(minWeight(W), -1e-12);
  EXPECT_LE(W.maxCoeff(), 1.0 + 1e-12);
}

TEST(HeatDiffusion, IterationsConvergeToTheSteadyState) {
  Points C(4, 2);
  C << 0, 0, 12, 0, 12, 12, 0, 12;
  const Cage cage = Cage::polygon(C);
  const SampleSet S = sampleCage(cage, 1.0, 0.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(1.0));
  const InitOptions unscreened;  // no locality: the iterations converge to the plain (unscreened) steady state
  const Weights Wss = initialWeights(S, cage, K, unscreened);
  double previous = 1e300;
  for (int n : {10, 100, 1000}) {
    InitOptions opt;
    opt.iterations = n;
    InitReport rep;
    const double err = (initialWeights(S, cage, K, opt, &rep) - Wss).cwiseAbs().maxCoeff();
    EXPECT_EQ(rep.iterations, n);
    EXPECT_LT(err, previous) << n << " iterations";
    previous = err;
  }
  EXPECT_LT(previous, 1e-4);
}

TEST(HeatDiffusion, FloorTargetsDropsTheTailOfInteriorAndExteriorRowsOnly) {
  SampleSet S;
  S.X.resize(5, 2);
  S.X << 0, 0, 1, 0, 0, 1, 0.5, 0.0, 0.2, 0.2;
  S.kind = {SampleKind::Control, SampleKind::Edge, SampleKind::Interior, SampleKind::Exterior, SampleKind::Interior};
  Weights W0(5, 3);
  W0 << 1.0, 0.0, 0.0,   // control: exact data
      0.98, 0.02, 0.0,   // edge: exact data, kept although 0.02 is below the floor
      0.02, 0.01, 0.97,  // a row whose tail is all below the floor
      0.5, 0.48, 0.02,   // exterior
      0.6, 0.2, 0.2;
  const Weights before = W0;
  floorTargets(S, W0, 0.0);
  EXPECT_EQ(W0, before) << "floor 0 changes nothing";
  floorTargets(S, W0, 0.03);
  EXPECT_EQ(W0.row(0), before.row(0));
  EXPECT_EQ(W0.row(1), before.row(1));
  EXPECT_EQ(W0(2, 0), 0.0);
  EXPECT_EQ(W0(2, 1), 0.0);
  EXPECT_NEAR(W0(2, 2), 1.0, 1e-15);
  EXPECT_NEAR(W0(3, 0), 0.47 / 0.92, 1e-15);
  EXPECT_NEAR(W0(3, 1), 0.45 / 0.92, 1e-15);
  EXPECT_EQ(W0(3, 2), 0.0);
  EXPECT_NEAR(W0(4, 0), 0.57 / 0.91, 1e-15);
  EXPECT_NEAR(W0(4, 1), 0.17 / 0.91, 1e-15);
  for (Index i = 0; i < W0.rows(); ++i) EXPECT_NEAR(W0.row(i).sum(), 1.0, 1e-15) << i;
  // A row with nothing above the floor is left as it is.
  Weights flat = Weights::Constant(5, 3, 1.0 / 3.0);
  floorTargets(S, flat, 0.4);
  EXPECT_EQ(flat, Weights::Constant(5, 3, 1.0 / 3.0));
  EXPECT_THROW(floorTargets(S, W0, -0.01), std::invalid_argument);
  EXPECT_THROW(floorTargets(S, W0, std::nan("")), std::invalid_argument);
  Weights short_(4, 3);
  EXPECT_THROW(floorTargets(S, short_, 0.03), std::invalid_argument);
}

TEST(HeatDiffusion, ScreeningMakesTargetsLocalAndKeepsRowsSummingToOne) {
  // A square with controls at its corners and edge midpoints: unscreened (harmonic-like) targets
  // near one corner still take a share from the far controls; screened ones (almost) none.
  const Cage cage = squareWithMidpoints(40.0);
  const Points& C = cage.C;
  const SampleSet S = sampleCage(cage, 1.0, 0.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(1.0));
  InitOptions global, local;  // global: no locality length, unscreened
  local.locality = 4.0;
  const Weights Wg = initialWeights(S, cage, K, global), Wl = initialWeights(S, cage, K, local);
  double farGlobal = 0.0, farLocal = 0.0;
  for (Index i = 0; i < S.size(); ++i) {
    EXPECT_NEAR(Wl.row(i).sum(), 1.0, 1e-12) << "row " << i;
    EXPECT_GE(Wl.row(i).minCoeff(), 0.0);
    if (S.kind[static_cast<std::size_t>(i)] == SampleKind::Control || S.kind[static_cast<std::size_t>(i)] == SampleKind::Edge) {
      EXPECT_EQ(Wl.row(i), Wg.row(i)) << "fixed row " << i;  // controls and edges are not screened
      continue;
    }
    if (S.kind[static_cast<std::size_t>(i)] != SampleKind::Interior || S.X.row(i).norm() > 8.0) continue;
    farGlobal = std::max(farGlobal, Wg(i, 3) + Wg(i, 4) + Wg(i, 5));  // controls ≥ 30 away
    farLocal = std::max(farLocal, Wl(i, 3) + Wl(i, 4) + Wl(i, 5));
  }
  // Screened rows reproduce their positions (so the QP (4.1) keeps them): Σ w_i c_i = x.
  for (Index i = 0; i < S.size(); ++i) {
    if (S.kind[static_cast<std::size_t>(i)] != SampleKind::Interior) continue;
    EXPECT_LT((Wl.row(i) * C - S.X.row(i)).cwiseAbs().maxCoeff(), 1e-9) << "row " << i;
  }
  EXPECT_GT(farGlobal, 1e-3);
  EXPECT_LT(farLocal, 0.05 * farGlobal) << "global " << farGlobal << ", screened " << farLocal;
}

TEST(HeatDiffusionSlow, ScreeningUnderflowFallsBackPerSample) {
  // A locality so short that heat underflows (row sums < 1e-200) a few samples into the square:
  // only those rows take the unscreened steady state; rows near the cage stay screened (local).
  const Cage cage = squareWithMidpoints(60.0);
  const SampleSet S = sampleCage(cage, 1.0, 0.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(1.0));
  InitOptions global, local;
  local.locality = 1e-16;  // ~1e-31 per kernel hop: underflow ~7 hops (30 px) from the cage
  InitReport report;
  const Weights Wg = initialWeights(S, cage, K, global), Wl = initialWeights(S, cage, K, local, &report);
  Index interior = 0;
  for (Index i = 0; i < S.size(); ++i) interior += S.kind[static_cast<std::size_t>(i)] == SampleKind::Interior;
  EXPECT_GT(report.unscreenedSamples, 0);
  EXPECT_LT(report.unscreenedSamples, interior / 2);
  ASSERT_TRUE(Wl.allFinite());
  double farGlobal = 0.0, farLocal = 0.0;
  for (Index i = 0; i < S.size(); ++i) {
    EXPECT_NEAR(Wl.row(i).sum(), 1.0, 1e-9) << "row " << i;  // the positional projection's tolerance
    EXPECT_GE(Wl.row(i).minCoeff(), 0.0);
    if (S.kind[static_cast<std::size_t>(i)] != SampleKind::Interior || S.X.row(i).norm() > 3.0) continue;
    farGlobal = std::max(farGlobal, Wg(i, 3) + Wg(i, 4) + Wg(i, 5));  // controls ≥ 50 away
    farLocal = std::max(farLocal, Wl(i, 3) + Wl(i, 4) + Wl(i, 5));
  }
  EXPECT_GT(farGlobal, 1e-4);
  EXPECT_LT(farLocal, 1e-3 * farGlobal) << "the corner's rows lost their screening";
}

TEST(HeatDiffusion, OneIterationIsTheRowNormalizedKernelUpdate) {
  // (4.12) with P = D⁻¹K on a convex cage (no pair crosses it): W_D ← P W for the non-controls.
  Points C(4, 2);
  C << 0, 0, 12, 0, 12, 9, 0, 9;
  const Cage cage = Cage::polygon(C);
  const SampleSet S = sampleCage(cage, 1.0, 0.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(1.0));
  InitOptions opt;
  opt.method = InitMethod::HeatImpulse;
  opt.iterations = 2;
  const Weights W = initialWeights(S, cage, K, opt);
  const Index m = 4, n = S.size();
  Weights ref = Weights::Zero(n, m);
  ref.topRows(m).setIdentity();
  const Eigen::VectorXd D = K * Eigen::VectorXd::Ones(n);
  for (int it = 0; it < 2; ++it) {
    Weights next = (D.cwiseInverse().asDiagonal() * (K * ref)).eval();
    next.topRows(m).setIdentity();
    ref = next;
  }
  EXPECT_LE((W - ref).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(HeatDiffusion, IsolatedSamplesGetSaneFallbackWeights) {
  const Cage cage = uCage();
  SampleSet S = sampleCage(cage, 3.0, 0.0);
  const Index n = S.size();
  S.X.conservativeResize(n + 1, 2);
  S.X.row(n) << 300.0, 300.0;  // far outside: no kernel neighbour at all
  S.kind.push_back(SampleKind::Exterior);
  S.edge.conservativeResize(n + 1, 2);
  S.edge.row(n) << -1, -1;
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(3.0));
  for (int iterations : {0, 10}) {
    InitOptions opt;
    opt.iterations = iterations;
    InitReport rep;
    const Weights W = initialWeights(S, cage, K, opt, &rep);
    EXPECT_TRUE(W.allFinite());
    EXPECT_EQ(rep.fallbackSamples, 1);
    EXPECT_NEAR(W.row(n).sum(), 1.0, 1e-12);
    EXPECT_GT(W.row(n).minCoeff(), 0.0);
  }
}

TEST(HeatDiffusion, InverseDistanceFollowsTheFormula) {
  const Cage cage = uCage();
  const SampleSet S = sampleCage(cage, 4.0, 0.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(4.0));
  InitOptions opt;
  opt.method = InitMethod::InverseDistance;
  opt.inverseDistanceP = 7.0;
  const Weights W = initialWeights(S, cage, K, opt);
  EXPECT_EQ(lagrangeError(W.topRows(8)), 0.0);
  for (Index j = 8; j < S.size(); j += 17)
    for (Index i = 0; i < 8; ++i) {
      const double r = (S.X.row(j) - cage.C.row(i)).norm() / 7.0;
      EXPECT_NEAR(W(j, i), 1.0 / (1.0 + r * r), 1e-15);  // (4.10)
    }
}

TEST(HeatDiffusionSlow, ThreadCountDoesNotChangeResults) {
  const Cage cage = uCage();
  const SampleSet S = sampleCage(cage, 1.5, 5.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(1.5));
  for (int iterations : {0, 30}) {
    InitOptions opt;
    opt.iterations = iterations;
    Weights W[2];
    for (int t : {1, 2}) {
      ScopedThreadCount threads(t);
      W[t - 1] = initialWeights(S, cage, K, opt);
    }
    EXPECT_TRUE(W[0] == W[1]) << iterations << " iterations";
  }
}

TEST(HeatDiffusion, RejectsBadInput) {
  const Cage cage = uCage();
  const SampleSet S = sampleCage(cage, 4.0, 0.0);
  const SparseMatrix K = assembleKernelMatrix(S.X, kernelFor(4.0));
  InitOptions opt;
  opt.iterations = -1;
  EXPECT_THROW(initialWeights(S, cage, K, opt), std::invalid_argument);
  const SparseMatrix Ksmall = assembleKernelMatrix(S.X.topRows(20), kernelFor(4.0));
  EXPECT_THROW(initialWeights(S, cage, Ksmall, InitOptions{}), std::invalid_argument);
  SampleSet bad = S;
  bad.kind[0] = SampleKind::Interior;  // controls must come first
  EXPECT_THROW(initialWeights(bad, cage, K, InitOptions{}), std::invalid_argument);
  for (double locality : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    InitOptions screened;
    screened.locality = locality;  // a length is finite and > 0; "off" is no length
    EXPECT_THROW(initialWeights(S, cage, K, screened), std::invalid_argument) << locality;
  }
}

}  // namespace
}  // namespace kc
