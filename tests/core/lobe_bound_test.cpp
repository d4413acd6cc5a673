// LobeBound: the field's weights projected onto w ≥ ℓ(x) where they dip below it (lobe_bound.h),
// on a smooth synthetic field with negative weights: QEC (4.2–4.6) of Gaussian targets, which keeps
// partition of unity and reproduction exactly and dips below 0 near every control's neighbours.
#include "kc/core/field/lobe_bound.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kc/core/weights/optimizer.h"
#include "kc/core/weights/sample_qp.h"
#include "random_point.h"

namespace kc {
namespace {

/// A 14-point star-shaped cage with radii 60–110 px round (200, 200).
Cage starCage() {
  const int m = 14;
  Points C(m, 2);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> r(60.0, 110.0);
  for (int i = 0; i < m; ++i) {
    const double a = 2.0 * M_PI * i / m, radius = r(rng);
    C.row(i) << 200.0 + radius * std::cos(a), 200.0 + radius * std::sin(a);
  }
  return Cage::polygon(C);
}

/// The synthetic field's weights at x: QEC of Gaussian targets of width s round the controls.
Eigen::RowVectorXd rawWeights(const Cage& cage, const ControlFrame& frame, const Vec2& x) {
  const Index m = cage.size();
  const double s = 35.0;
  std::vector<double> w0(static_cast<std::size_t>(m)), w(static_cast<std::size_t>(m));
  for (Index j = 0; j < m; ++j) w0[std::size_t(j)] = std::exp(-(x - Vec2(cage.C.row(j))).squaredNorm() / (2.0 * s * s));
  sampleQec(frame, frame.normalize(x), w0, w);
  return Eigen::Map<Eigen::RowVectorXd>(w.data(), m);
}

Weights rawWeights(const Cage& cage, const Points& P) {
  const ControlFrame frame(cage.C);
  Weights W(P.rows(), cage.size());
  for (Index i = 0; i < P.rows(); ++i) W.row(i) = rawWeights(cage, frame, P.row(i).transpose());
  return W;
}

/// Random points over the cage's bounding box grown by 40 px.
Points randomPoints(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(50.0, 350.0);
  Points P(count, 2);
  for (int i = 0; i < count; ++i) P.row(i) = test::randomPoint(u, rng).transpose();
  return P;
}

constexpr double kDepth = 0.0125, kFade = 20.0;

/// Each case in the Euclidean metric and in the QP's allowance metric (ε = 0.005, kQpAllowance).
class LobeBoundMetric : public ::testing::TestWithParam<double> {};

/// The star cage, its bound in the metric ε, `count` random points, the raw weights there and the
/// bounded ones (the rows `changed`).
struct Bounded {
  Bounded(double eps, int count, unsigned seed)
      : cage(starCage()),
        bound(cage, kDepth, kFade, eps),
        P(randomPoints(count, seed)),
        raw(rawWeights(cage, P)),
        W(raw),
        changed(bound.apply(P, W)) {}
  Cage cage;
  LobeBound bound;
  Points P;
  Weights raw, W;
  std::vector<Index> changed;
};

TEST_P(LobeBoundMetric, ProjectsOnlyTheRowsBelowTheBoundAndKeepsTheConstraints) {
  const Bounded b(GetParam(), 3000, 3);
  const auto& [cage, bound, P, raw, W, changed] = b;
  const CageQueries queries(cage);
  Index inside = 0, below = 0;
  std::size_t next = 0;
  for (Index i = 0; i < P.rows(); ++i) {
    const Vec2 x = P.row(i).transpose();
    const double l = bound.bound(x);
    EXPECT_EQ(l, queries.inside(x) ? -kDepth : -kDepth - queries.distance(x) / kFade);
    const bool isChanged = next < changed.size() && changed[next] == i;
    if (isChanged) ++next;
    if (raw.row(i).minCoeff() >= l) {
      EXPECT_FALSE(isChanged);
      EXPECT_EQ(W.row(i), raw.row(i)) << "row " << i << " is above its bound and must be kept bit for bit";
      continue;
    }
    ++below;
    inside += queries.inside(x) ? 1 : 0;
    EXPECT_TRUE(isChanged);
    EXPECT_GE(W.row(i).minCoeff(), l - 1e-12);
    EXPECT_NEAR(W.row(i).sum(), 1.0, 1e-12);
    EXPECT_LT((W.row(i) * cage.C - x.transpose()).cwiseAbs().maxCoeff(), 1e-9);
  }
  EXPECT_EQ(next, changed.size());
  // The synthetic field dips below the bound in many places, inside and outside.
  EXPECT_GT(inside, 100);
  EXPECT_GT(below - inside, 20);
}

TEST_P(LobeBoundMetric, TheProjectionIsTheQpOptimum) {
  // KKT of min Σ (v − w)²/a s.t. Av = b, v ≥ ℓ (convex, so sufficient): (v − w)/a = Aᵀλ + μ with
  // μ ≥ 0 on the active set and 0 off it. λ from the free entries by least squares, then μ checked.
  const double eps = GetParam();
  const Bounded b(eps, 1500, 5);
  const auto& [cage, bound, P, raw, W, changed] = b;
  ASSERT_GT(changed.size(), 100u);
  const Index m = cage.size();
  for (Index i : changed) {
    const double l = bound.bound(P.row(i).transpose());
    Eigen::RowVectorXd d = W.row(i) - raw.row(i);
    if (eps > 0.0)
      for (Index j = 0; j < m; ++j) d(j) /= allowanceOf(raw(i, j), eps);
    std::vector<Index> free;
    for (Index j = 0; j < m; ++j)
      if (W(i, j) > l + 1e-10) free.push_back(j);
    ASSERT_GE(free.size(), 3u);
    Eigen::MatrixXd AF(3, static_cast<Index>(free.size()));
    Eigen::VectorXd dF(static_cast<Index>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k) {
      AF.col(Index(k)) << cage.C(free[k], 0), cage.C(free[k], 1), 1.0;
      dF(Index(k)) = d(free[k]);
    }
    const Eigen::Vector3d lambda = AF.transpose().colPivHouseholderQr().solve(dF);
    EXPECT_LT((AF.transpose() * lambda - dF).cwiseAbs().maxCoeff(), 1e-9) << "row " << i;
    for (Index j = 0; j < m; ++j) {
      if (W(i, j) > l + 1e-10) continue;
      const double mu = d(j) - Eigen::Vector3d(cage.C(j, 0), cage.C(j, 1), 1.0).dot(lambda);
      EXPECT_GE(mu, -1e-9) << "row " << i << ", control " << j;
    }
  }
}

TEST_P(LobeBoundMetric, IsContinuousAcrossTheCage) {
  // Segments through the cage's edges at their midpoints, 20 px each side, in steps of 0.005 px:
  // the bounded weights change per step by at most a few times what the raw field and the
  // bound's slope outside (1/fade) allow together.
  const Cage cage = starCage();
  const LobeBound bound(cage, kDepth, kFade, GetParam());
  const Index m = cage.size();
  const double step = 0.005;
  for (Index e = 0; e < m; ++e) {
    const Vec2 a = cage.C.row(e), b = cage.C.row((e + 1) % m);
    const Vec2 mid = 0.5 * (a + b), n = Vec2(b.y() - a.y(), a.x() - b.x()).normalized();
    const int count = static_cast<int>(40.0 / step) + 1;
    Points P(count, 2);
    for (int k = 0; k < count; ++k) P.row(k) = (mid + (-20.0 + step * k) * n).transpose();
    const Weights raw = rawWeights(cage, P);
    Weights W = raw;
    bound.apply(P, W);
    double rawStep = 0.0, boundedStep = 0.0;
    for (int k = 0; k + 1 < count; ++k) {
      rawStep = std::max(rawStep, (raw.row(k + 1) - raw.row(k)).cwiseAbs().maxCoeff());
      boundedStep = std::max(boundedStep, (W.row(k + 1) - W.row(k)).cwiseAbs().maxCoeff());
    }
    EXPECT_LE(boundedStep, 4.0 * (rawStep + step / kFade)) << "edge " << e;
  }
}

TEST_P(LobeBoundMetric, GradientsMatchFiniteDifferences) {
  const Bounded b(GetParam(), 800, 9);
  const auto& [cage, bound, P, raw, W, changed] = b;
  ASSERT_GT(changed.size(), 50u);
  // The raw field's gradients (QEC of smooth targets: central differences are accurate to ~1e-8).
  const double e = 1e-4;
  auto at = [&](const Vec2& x, bool bounded) {
    Points Q(1, 2);
    Q.row(0) = x.transpose();
    Weights w = rawWeights(cage, Q);
    if (bounded) bound.apply(Q, w);
    return Eigen::RowVectorXd(w.row(0));
  };
  Weights dx(P.rows(), cage.size()), dy(P.rows(), cage.size());
  for (Index i = 0; i < P.rows(); ++i) {
    const Vec2 x = P.row(i).transpose();
    dx.row(i) = (at(x + Vec2(e, 0), false) - at(x - Vec2(e, 0), false)) / (2 * e);
    dy.row(i) = (at(x + Vec2(0, e), false) - at(x - Vec2(0, e), false)) / (2 * e);
  }
  const Weights dx0 = dx, dy0 = dy;
  bound.applyGradients(P, raw, dx, dy);
  Index compared = 0;
  std::size_t next = 0;
  for (Index i = 0; i < P.rows(); ++i) {
    const bool isChanged = next < changed.size() && changed[next] == i;
    if (isChanged) ++next;
    if (!isChanged) {
      EXPECT_EQ(dx.row(i), dx0.row(i));
      EXPECT_EQ(dy.row(i), dy0.row(i));
      continue;
    }
    const Vec2 x = P.row(i).transpose();
    // Skip points within a step of a kink (the one-sided differences disagree there).
    const Eigen::RowVectorXd c = at(x, true);
    const Eigen::RowVectorXd fx = (at(x + Vec2(e, 0), true) - c) / e, bx = (c - at(x - Vec2(e, 0), true)) / e;
    const Eigen::RowVectorXd fy = (at(x + Vec2(0, e), true) - c) / e, by = (c - at(x - Vec2(0, e), true)) / e;
    if ((fx - bx).cwiseAbs().maxCoeff() > 1e-5 || (fy - by).cwiseAbs().maxCoeff() > 1e-5) continue;
    ++compared;
    EXPECT_LT((dx.row(i) - 0.5 * (fx + bx)).cwiseAbs().maxCoeff(), 1e-6) << "row " << i;
    EXPECT_LT((dy.row(i) - 0.5 * (fy + by)).cwiseAbs().maxCoeff(), 1e-6) << "row " << i;
  }
  EXPECT_GT(compared, 50);
}

INSTANTIATE_TEST_SUITE_P(EuclideanAndAllowance, LobeBoundMetric, ::testing::Values(0.0, 0.005));

TEST(LobeBound, SampleQpAboveWithBoundZeroIsTheQp) {
  const Cage cage = starCage();
  const ControlFrame frame(cage.C);
  const Points P = randomPoints(300, 13);
  const CageQueries queries(cage);
  const Index m = cage.size();
  Index checked = 0;
  for (Index i = 0; i < P.rows(); ++i) {
    const Vec2 x = P.row(i).transpose();
    if (!queries.inside(x)) continue;
    const Eigen::RowVectorXd w0 = rawWeights(cage, frame, x);
    std::vector<double> target(w0.data(), w0.data() + m), a(static_cast<std::size_t>(m)), b(static_cast<std::size_t>(m));
    sampleQp(frame, frame.normalize(x), target, a);
    sampleQpAbove(frame, frame.normalize(x), target, 0.0, {}, b);
    for (Index j = 0; j < m; ++j) EXPECT_NEAR(a[std::size_t(j)], b[std::size_t(j)], 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 50);
  std::vector<double> target(static_cast<std::size_t>(m), 1.0 / double(m)), w(static_cast<std::size_t>(m));
  EXPECT_THROW(sampleQpAbove(frame, Vec2::Zero(), target, 0.1, {}, w), std::invalid_argument);
}

TEST(LobeBound, RefusesBadInput) {
  const Cage cage = starCage();
  EXPECT_THROW(LobeBound(cage, -0.01, kFade), std::invalid_argument);
  EXPECT_THROW(LobeBound(cage, std::nan(""), kFade), std::invalid_argument);
  EXPECT_THROW(LobeBound(cage, kDepth, 0.0), std::invalid_argument);
  EXPECT_THROW(LobeBound(cage, kDepth, kFade, -1.0), std::invalid_argument);
  Cage open;  // sticks: no interior
  open.C = cage.C.topRows(4);
  open.edges = {{0, 1}, {1, 2}, {2, 3}};
  open.closed = false;
  EXPECT_THROW(LobeBound(open, kDepth, kFade), std::invalid_argument);
  const LobeBound bound(cage, kDepth, kFade);
  const Points P = randomPoints(10, 1);
  Weights W(10, cage.size() - 1);
  EXPECT_THROW(bound.apply(P, W), std::invalid_argument);
}

}  // namespace
}  // namespace kc
