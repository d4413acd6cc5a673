// The exterior rows continued from the inside (ExteriorContinuation): exact partition of unity and
// reproduction, linear weights continued unchanged, gaps and far rows left alone, refined gaps
// blending their two walls (and only below the blend's width), subsets and thread counts giving the
// same rows.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kc/core/parallel.h"
#include "kc/core/sizing.h"
#include "kc/core/weights/exterior_continuation.h"
#include "kc/core/weights/optimizer.h"

namespace kc {
namespace {

/// Samples of a closed polygon on a grid of step h over [x0, x1]×[y0, y1]: the controls, every
/// grid point inside (Interior) or outside (Exterior) the cage farther than h/4 from it, and edge
/// samples every h along every edge.
SampleSet gridSamples(const Cage& cage, double h, double x0, double y0, double x1, double y1) {
  std::vector<Vec2> X;
  std::vector<SampleKind> kind;
  std::vector<std::array<int, 2>> edge;
  const Index m = cage.size();
  for (Index i = 0; i < m; ++i) {
    X.push_back(cage.C.row(i).transpose());
    kind.push_back(SampleKind::Control);
    edge.push_back({-1, -1});
  }
  for (const auto& [a, b] : cageEdges(cage)) {
    const Vec2 ca = cage.C.row(a), cb = cage.C.row(b);
    const int n = std::max(1, static_cast<int>(std::round((cb - ca).norm() / h)));
    for (int k = 1; k < n; ++k) {
      X.push_back(ca + (cb - ca) * (static_cast<double>(k) / n));
      kind.push_back(SampleKind::Edge);
      edge.push_back({a, b});
    }
  }
  const CageQueries q(cage);
  for (double y = y0; y <= y1; y += h)
    for (double x = x0; x <= x1; x += h) {
      const Vec2 p(x + 0.37 * h * std::sin(3.1 * x + y), y + 0.29 * h * std::cos(x - 2.3 * y));  // not on a lattice
      if (q.distance(p) < 0.25 * h) continue;
      X.push_back(p);
      kind.push_back(q.inside(p) ? SampleKind::Interior : SampleKind::Exterior);
      edge.push_back({-1, -1});
    }
  SampleSet S;
  S.X.resize(static_cast<Index>(X.size()), 2);
  S.edge.resize(static_cast<Index>(X.size()), 2);
  for (std::size_t i = 0; i < X.size(); ++i) {
    S.X.row(static_cast<Index>(i)) = X[i].transpose();
    S.edge.row(static_cast<Index>(i)) << edge[i][0], edge[i][1];
  }
  S.kind = kind;
  return S;
}

/// Appends exterior samples at `points` to S; returns the index of the first.
Index addExteriorSamples(SampleSet& S, const std::vector<Vec2>& points) {
  const Index first = S.size(), n = static_cast<Index>(points.size());
  S.X.conservativeResize(first + n, 2);
  S.edge.conservativeResize(first + n, 2);
  for (Index k = 0; k < n; ++k) {
    S.X.row(first + k) = points[static_cast<std::size_t>(k)].transpose();
    S.edge.row(first + k) << -1, -1;
    S.kind.push_back(SampleKind::Exterior);
  }
  return first;
}

constexpr double kSceneSpacing = 10.0;

/// A polygon's grid samples (gridSamples, h = kSceneSpacing, over box = {x0, y0, x1, y1}) with
/// exterior samples added at `extra` (from index `first` on), and their continuation.
struct Scene {
  Cage cage;
  SampleSet S;
  Index first = 0;
  ExteriorContinuation c;
};
Scene polygonScene(const Points& C, const std::array<double, 4>& box, const std::vector<Vec2>& extra) {
  Scene s;
  s.cage = Cage::polygon(C);
  s.S = gridSamples(s.cage, kSceneSpacing, box[0], box[1], box[2], box[3]);
  s.first = addExteriorSamples(s.S, extra);
  s.c = ExteriorContinuation(s.S, s.cage, kSceneSpacing, nullptr);
  return s;
}

/// Rows that sum to 1 and reproduce their positions, from random targets (QEC keeps them exact).
Weights randomExactRows(const SampleSet& S, const Cage& cage, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Weights W0(S.size(), cage.size());
  for (Index i = 0; i < W0.rows(); ++i)
    for (Index k = 0; k < W0.cols(); ++k) W0(i, k) = u(rng);
  Weights W;
  WeightOptimizer(cage.C).optimize(S, W0, W, Method::QEC);
  return W;
}

double worstUnity(const Weights& W, const std::vector<Index>& rows) {
  double e = 0.0;
  for (Index i : rows) e = std::max(e, std::abs(W.row(i).sum() - 1.0));
  return e;
}

double worstReproduction(const Weights& W, const Points& C, const Points& X, const std::vector<Index>& rows) {
  double e = 0.0;
  for (Index i : rows) e = std::max(e, (W.row(i) * C - X.row(i)).cwiseAbs().maxCoeff());
  return e;
}

Cage uCage() {
  Points C(8, 2);
  C << 10, 10, 40, 10, 40, 60, 60, 60, 60, 10, 90, 10, 90, 90, 10, 90;  // a notch 20 px wide from the top
  return Cage::polygon(C);
}

TEST(ExteriorContinuation, KeepsPartitionOfUnityAndReproductionExact) {
  const Cage cage = uCage();
  const SampleSet S = gridSamples(cage, 4.0, -10, -10, 110, 110);
  const ExteriorContinuation c(S, cage, 4.0, nullptr);
  ASSERT_GT(c.rows().size(), 50u);
  Weights W = randomExactRows(S, cage, 7);
  const Weights before = W;
  c.apply(W);
  EXPECT_LE(worstUnity(W, c.rows()), 1e-12);
  EXPECT_LE(worstReproduction(W, cage.C, S.X, c.rows()), 1e-10);
  // Only the continued rows change, and they do.
  std::vector<char> continued(static_cast<std::size_t>(S.size()), 0);
  for (Index i : c.rows()) {
    continued[static_cast<std::size_t>(i)] = 1;
    EXPECT_EQ(S.kind[static_cast<std::size_t>(i)], SampleKind::Exterior);
  }
  double moved = 0.0;
  for (Index i = 0; i < S.size(); ++i) {
    if (!continued[static_cast<std::size_t>(i)])
      EXPECT_EQ((W.row(i) - before.row(i)).cwiseAbs().maxCoeff(), 0.0) << "row " << i;
    else
      moved = std::max(moved, (W.row(i) - before.row(i)).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(moved, 0.1);
}

TEST(ExteriorContinuation, ContinuesLinearWeightsUnchanged) {
  // A triangle's barycentric coordinates are linear: their odd reflection through an edge is
  // themselves, so rows that hold them outside stay as they are.
  Points C(3, 2);
  C << 20, 20, 100, 30, 40, 100;
  const Cage cage = Cage::polygon(C);
  const SampleSet S = gridSamples(cage, 4.0, 0, 0, 120, 120);
  Eigen::Matrix3d A;
  A << C(0, 0), C(1, 0), C(2, 0), C(0, 1), C(1, 1), C(2, 1), 1, 1, 1;
  const Eigen::Matrix3d Ainv = A.inverse();
  Weights W(S.size(), 3);
  for (Index i = 0; i < S.size(); ++i) W.row(i) = (Ainv * Eigen::Vector3d(S.X(i, 0), S.X(i, 1), 1.0)).transpose();
  const Weights barycentric = W;
  const ExteriorContinuation c(S, cage, 4.0, nullptr);
  ASSERT_GT(c.rows().size(), 30u);
  c.apply(W);
  EXPECT_LE((W - barycentric).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ExteriorContinuation, LeavesNarrowGapsAndFarRowsAlone) {
  // The U's notch is 20 px wide, no wider than the band at h = 10 (2h): no row inside the notch is
  // continued; nor is any row farther than the band from the cage.
  const Cage cage = uCage();
  const double h = 10.0;
  const SampleSet S = gridSamples(cage, h, -20, -20, 120, 120);
  const ExteriorContinuation c(S, cage, h, nullptr);
  ASSERT_FALSE(c.rows().empty());
  const CageQueries q(cage);
  for (Index i : c.rows()) {
    const Vec2 x = S.X.row(i);
    EXPECT_LT(q.distance(x), ExteriorContinuationOptions{}.bandSpacings * h) << "row " << i;
    EXPECT_FALSE(x.x() > 40 && x.x() < 60 && x.y() > 10 && x.y() < 60) << "row " << i << " in the notch";
  }
}

TEST(ExteriorContinuation, ContinuesInAWideOutsideWedge) {
  // The right side bends inward by 14° at (85, 50), an outside wedge of 166°. Samples in it, about
  // 3 px from both edges, which lie on the same side of them (no gap), are continued like any
  // other within the band (a notch, whose walls face each other: LeavesNarrowGapsAndFarRowsAlone).
  Points C(5, 2);
  C << 10, 10, 90, 10, 85, 50, 90, 90, 10, 90;
  const auto [cage, S, first, c] = polygonScene(C, {-20, -20, 120, 120}, {{88.0, 50.0}, {88.3, 47.0}, {88.3, 53.0}});
  for (Index i = first; i < S.size(); ++i)
    EXPECT_TRUE(std::binary_search(c.rows().begin(), c.rows().end(), i)) << "row " << i << " at " << S.X.row(i);
}

TEST(ExteriorContinuation, TheFarSideOfAConvexPartIsNoGapWall) {
  // A leg whose right side (x = 40) flares out to a foot at its bottom. A sample 6 px right of the
  // leg, 18 px above the foot's outer corner, sees that corner across the outside, but the cage
  // between the two walls turns towards the inside (round the foot), so the corner bounds no gap:
  // the row keeps the single-side share of its optimized weights, smoothstep(d / band), where
  // counting the corner as a gap's far wall would leave it nearly all of them.
  Points C(5, 2);
  C << 20, 0, 40, 0, 40, 70, 46, 84, 14, 86;
  const auto [cage, S, row, c] = polygonScene(C, {-30, -30, 90, 120}, {{46.0, 66.0}});
  ASSERT_TRUE(std::binary_search(c.rows().begin(), c.rows().end(), row));
  // keep = the change of the continued row per unit change of the row's own optimized weights.
  Weights A = randomExactRows(S, cage, 3), B = A;
  B.row(row) = randomExactRows(S, cage, 4).row(row);
  const Eigen::RowVectorXd own = A.row(row) - B.row(row);
  c.apply(A);
  c.apply(B);
  Index k = 0;
  own.cwiseAbs().maxCoeff(&k);
  const double keep = (A(row, k) - B(row, k)) / own(k);
  const double u = 6.0 / (ExteriorContinuationOptions{}.bandSpacings * kSceneSpacing);
  EXPECT_NEAR(keep, u * u * (3.0 - 2.0 * u), 1e-9);
}

TEST(ExteriorContinuation, ARefinedGapBlendsItsTwoWallsAndNextToAWallContinuesThatWallAlone) {
  // The U's notch (x in 40..60, open at the top, 50 px deep) is narrow for hMax = 24 (20 px <
  // kOutsideNarrowWidth·hMax): the sizing refines it (h = 20/k), and its exterior rows, left alone by a
  // uniform sampling (LeavesNarrowGapsAndFarRowsAlone), blend the reflections of both walls.
  const Cage cage = uCage();
  SizingOptions so;
  so.hMax = 24.0;
  const SizingField sizing = featureSizing(cage, {}, so);
  ASSERT_TRUE(sizing.graded());
  ASSERT_LT(sizing(Vec2(50, 30)), 0.5 * so.hMax);
  const SampleSet S = gridSamples(cage, 2.5, -10, -10, 110, 110);
  const ExteriorContinuation c(S, cage, so.hMax, &sizing);
  const CageQueries q(cage);
  auto inNotch = [](const Vec2& x) { return x.x() > 40 && x.x() < 60 && x.y() > 15 && x.y() < 35; };
  std::vector<Index> notch;
  for (Index i = 0; i < S.size(); ++i)
    if (S.kind[std::size_t(i)] == SampleKind::Exterior && inNotch(S.X.row(i))) notch.push_back(i);
  ASSERT_GT(notch.size(), 40u);
  for (Index i : notch) EXPECT_TRUE(std::binary_search(c.rows().begin(), c.rows().end(), i)) << "row " << i << " at " << S.X.row(i);
  Weights W = randomExactRows(S, cage, 5);
  Weights changed = W;
  // Change the rows of the notch's left side (x < 40): rows next to the right wall (within a fifth
  // of the gap) read none of them; rows in the middle read both sides.
  for (Index i = 0; i < S.size(); ++i)
    if (S.kind[std::size_t(i)] != SampleKind::Exterior && S.X(i, 0) < 40) changed.row(i).array() += 0.1 * double(i % 7);
  c.apply(W);
  c.apply(changed);
  EXPECT_LE(worstUnity(W, c.rows()), 1e-12);
  EXPECT_LE(worstReproduction(W, cage.C, S.X, c.rows()), 1e-10);
  int nearRight = 0, middle = 0;
  for (Index i : notch) {
    const double x = S.X(i, 0), diff = (changed.row(i) - W.row(i)).cwiseAbs().maxCoeff();
    if (x > 56.5) {
      ++nearRight;
      EXPECT_EQ(diff, 0.0) << "row " << i << " at " << S.X.row(i);
    } else if (std::abs(x - 50.0) < 2.0) {
      ++middle;
      EXPECT_GT(diff, 1e-3) << "row " << i << " at " << S.X.row(i);
    }
  }
  EXPECT_GT(nearRight, 5);
  EXPECT_GT(middle, 5);
}

TEST(ExteriorContinuation, AGapWiderThanTheBlendWidthContinuesItsNearerWallAlone) {
  // The notch of the test above, 20 px wide at hMax = 24, with the blend's width limit below it
  // (blendWidth 0.3·hMax: a sizing that refines only narrower gaps, SizingOptions'
  // outsideNarrowWidth): its rows keep the single-side rule, so a row nearer the right wall reads
  // nothing of the left side; with the default limit the rows there read both walls.
  const Cage cage = uCage();
  SizingOptions so;
  so.hMax = 24.0;
  const SizingField sizing = featureSizing(cage, {}, so);
  const SampleSet S = gridSamples(cage, 2.5, -10, -10, 110, 110);
  ExteriorContinuationOptions narrow;
  narrow.blendWidth = 0.3;
  const ExteriorContinuation blended(S, cage, so.hMax, &sizing), single(S, cage, so.hMax, &sizing, narrow);
  const Weights W = randomExactRows(S, cage, 5);
  Weights changed = W;
  for (Index i = 0; i < S.size(); ++i)
    if (S.kind[std::size_t(i)] != SampleKind::Exterior && S.X(i, 0) < 40) changed.row(i).array() += 0.1 * double(i % 7);
  Weights Wb = W, Cb = changed, Ws = W, Cs = changed;
  blended.apply(Wb);
  blended.apply(Cb);
  single.apply(Ws);
  single.apply(Cs);
  EXPECT_LE(worstUnity(Ws, single.rows()), 1e-12);
  EXPECT_LE(worstReproduction(Ws, cage.C, S.X, single.rows()), 1e-10);
  int rightHalf = 0, readBoth = 0, continued = 0;
  for (Index i = 0; i < S.size(); ++i) {
    const double x = S.X(i, 0), y = S.X(i, 1);
    if (S.kind[std::size_t(i)] != SampleKind::Exterior || !(x > 50.5 && x < 56.5 && y > 15 && y < 35)) continue;
    ++rightHalf;
    readBoth += (Cb.row(i) - Wb.row(i)).cwiseAbs().maxCoeff() > 1e-3;
    continued += std::binary_search(single.rows().begin(), single.rows().end(), i);
    EXPECT_EQ((Cs.row(i) - Ws.row(i)).cwiseAbs().maxCoeff(), 0.0) << "row " << i << " at " << S.X.row(i);
  }
  EXPECT_GT(rightHalf, 10);
  EXPECT_GT(readBoth, 5);
  EXPECT_GT(continued, 5);
}

TEST(ExteriorContinuation, SubsetsAndThreadCountsGiveTheSameRows) {
  const Cage cage = uCage();
  const SampleSet S = gridSamples(cage, 4.0, -10, -10, 110, 110);
  const ExteriorContinuation c(S, cage, 4.0, nullptr);
  const Weights W0 = randomExactRows(S, cage, 11);
  Weights all = W0, some = W0, one = W0;
  c.apply(all);
  std::vector<Index> odd;
  for (std::size_t k = 1; k < c.rows().size(); k += 2) odd.push_back(c.rows()[k]);
  c.apply(some, odd);
  for (Index i : odd) EXPECT_EQ((some.row(i) - all.row(i)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((some.row(c.rows()[0]) - W0.row(c.rows()[0])).cwiseAbs().maxCoeff(), 0.0);  // not asked: untouched
  {
    const ScopedThreadCount single(1);
    const ExteriorContinuation c1(S, cage, 4.0, nullptr);
    EXPECT_EQ(c1.rows(), c.rows());
    c1.apply(one);
  }
  EXPECT_EQ((one - all).cwiseAbs().maxCoeff(), 0.0);
  const Index inside = 0;  // a control row
  EXPECT_THROW(c.apply(some, std::vector<Index>{inside}), std::invalid_argument);
}

}  // namespace
}  // namespace kc
