#include "kc/core/metrics.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace kc {
namespace {

Points unitSquare() {
  Points C(4, 2);
  C << 0, 0, 1, 0, 1, 1, 0, 1;
  return C;
}

/// Bilinear weights on the unit square: exact partition of unity, reproduction and Lagrange.
Weights bilinear(const Points& P) {
  Weights W(P.rows(), 4);
  for (Index p = 0; p < P.rows(); ++p) {
    const double x = P(p, 0), y = P(p, 1);
    W.row(p) << (1 - x) * (1 - y), x * (1 - y), x * y, (1 - x) * y;
  }
  return W;
}

TEST(Metrics, ExactCoordinatesScoreZero) {
  Points P(5, 2);
  P << 0.2, 0.3, 0.5, 0.5, 0.9, 0.1, 0.0, 0.4, 0.7, 1.0;
  const Points C = unitSquare();
  const Weights W = bilinear(P);
  EXPECT_LE(partitionOfUnityError(W), 1e-15);
  EXPECT_LE(reproductionError(W, C, P), 1e-15);
  EXPECT_LE(lagrangeError(bilinear(C)), 0.0);
  // P rows 3 and 4 lie on edges (3, 0) and (2, 3).
  EXPECT_LE(edgeLinearityError(W.bottomRows(2), C, P.bottomRows(2), {{3, 0}, {2, 3}}), 1e-15);
  EXPECT_GE(minWeight(W), 0.0);
  EXPECT_EQ(negativeCount(W), 0);
}

TEST(Metrics, DetectsEachViolation) {
  Points P(2, 2);
  P << 0.25, 0.5, 0.5, 0.0;  // second point on edge (0, 1)
  const Points C = unitSquare();
  Weights W = bilinear(P);
  W(0, 2) += 0.1;  // breaks partition of unity by 0.1 and reproduction by 0.1 in x and y
  EXPECT_NEAR(partitionOfUnityError(W), 0.1, 1e-15);
  EXPECT_NEAR(reproductionError(W, C, P), 0.1, 1e-15);
  W(1, 3) = 0.05;  // a weight of a far control on an edge point
  EXPECT_NEAR(edgeLinearityError(W.bottomRows(1), C, P.bottomRows(1), {{0, 1}}), 0.05, 1e-15);
  Weights Wc = bilinear(C);
  Wc(2, 1) = -0.02;
  EXPECT_NEAR(lagrangeError(Wc), 0.02, 1e-15);
  EXPECT_NEAR(minWeight(Wc), -0.02, 1e-15);
  EXPECT_EQ(negativeCount(Wc), 1);
  EXPECT_EQ(negativeCount(Wc, 0.05), 0);
}

TEST(Metrics, LocalityStatsFollowLbcDefinitions) {
  // Three points with areas 1, 2, 1 and m = 2 controls; the negligible threshold is 1e-3/2.
  Weights W(3, 2);
  W << 1.0, 0.0,    //
      0.6, 0.4,     //
      1e-4, -0.3;   // both below the threshold of (21): σ = 0
  Eigen::VectorXd area(3);
  area << 1, 2, 1;
  const LocalityStats s = localityStats(W, area, {0.0, 0.35, 1.0});
  // φ_1(t) areas: |w| ≤ 0 → {}; ≤ 0.35 → {p3}; ≤ 1 → all. φ_2: {p1}; {p1, p3}; all. /4, mean over i.
  ASSERT_EQ(s.P.size(), 3u);
  EXPECT_DOUBLE_EQ(s.P[0], (0.0 + 1.0) / 4 / 2);
  EXPECT_DOUBLE_EQ(s.P[1], (1.0 + 2.0) / 4 / 2);
  EXPECT_DOUBLE_EQ(s.P[2], 1.0);
  // σ = 1, 2, 0 with areas 1, 2, 1: Q(0) = 1, Q(1) = 3/4, Q(2) = 2/4.
  ASSERT_EQ(s.Q.size(), 3u);
  EXPECT_DOUBLE_EQ(s.Q[0], 1.0);
  EXPECT_DOUBLE_EQ(s.Q[1], 0.75);
  EXPECT_DOUBLE_EQ(s.Q[2], 0.5);
  EXPECT_DOUBLE_EQ(s.meanInfluencing, (1 * 1 + 2 * 2 + 0 * 1) / 4.0);
  EXPECT_EQ(s.maxInfluencing, 2);
}

TEST(Metrics, RejectsInconsistentShapes) {
  const Points C = unitSquare();
  Points P(2, 2);
  P << 0.1, 0.1, 0.2, 0.2;
  EXPECT_THROW(reproductionError(Weights::Zero(2, 3), C, P), std::invalid_argument);
  EXPECT_THROW(reproductionError(Weights::Zero(3, 4), C, P), std::invalid_argument);
  EXPECT_THROW(lagrangeError(Weights::Zero(3, 4)), std::invalid_argument);
  EXPECT_THROW(edgeLinearityError(Weights::Zero(2, 4), C, P, {{0, 1}}), std::invalid_argument);
  EXPECT_THROW(edgeLinearityError(Weights::Zero(1, 4), C, P.topRows(1), {{0, 7}}), std::invalid_argument);
  EXPECT_THROW(localityStats(Weights::Zero(2, 4), Eigen::VectorXd::Ones(3), {0.1}), std::invalid_argument);
  EXPECT_THROW(localityStats(Weights::Zero(2, 4), Eigen::VectorXd::Zero(2), {0.1}), std::invalid_argument);
}

}  // namespace
}  // namespace kc
