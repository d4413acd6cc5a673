#include "kc/core/field/line_correction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "kc/core/field/kernel_field.h"
#include "kc/core/structure/lines.h"
#include "point_problems.h"

namespace kc {
namespace {

constexpr double kSquareSide = 60.0;

/// A kernel field over a square cage of side kSquareSide (corners counter-clockwise from the origin) whose
/// sample weights are the square's bilinear coordinates: they sum to 1 and reproduce the samples, so
/// the exact interpolant does everywhere. Samples on a jittered grid of spacing 3 px around it.
struct SquareField {
  Cage cage;
  KernelField field;
};

std::unique_ptr<SquareField> squareField() {
  auto s = std::make_unique<SquareField>();
  Points C(4, 2);
  C << 0, 0, kSquareSide, 0, kSquareSide, kSquareSide, 0, kSquareSide;
  s->cage = Cage::polygon(C);
  const Points X = test::jitteredGrid(26, 3.0, 0.2, 5, Vec2(-7.5, -7.5));
  Weights W(X.rows(), 4);
  for (Index i = 0; i < X.rows(); ++i) {
    const double u = X(i, 0) / kSquareSide, v = X(i, 1) / kSquareSide;
    W.row(i) << (1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v;
  }
  EXPECT_EQ(s->field.compute(X, test::kernelFor(3.0), InterpMode::Exact).status, SolveStatus::Ok);
  s->field.update(W);
  return s;
}

/// An X of two crossing lines, a line ending 1 px from the right edge, and a parallel pair (group 0).
std::vector<StructureLine> drawnLines() {
  return {{{10, 10}, {40, 40}, -1}, {{10, 40}, {40, 10}, -1}, {{30, 25}, {59, 25}, -1}, {{8, 50}, {38, 50}, 0}, {{8, 55}, {38, 55}, 0}};
}

/// n equally spaced points from a to b.
Points along(const StructureLine& l, int n) { return lineSamplePoints(l, l.length() / double(n - 1)); }

TEST(LineCorrection, LinesAreLinearAndTheFieldKeepsUnityAndReproduction) {
  auto s = squareField();
  const std::vector<StructureLine> lines = drawnLines();
  const Points probe = test::randomPointsIn(400, 0.5, kSquareSide - 0.5, 3);
  const Weights plain = s->field.weightsAt(probe);
  const auto correction = std::make_shared<LineCorrection>(s->cage, lines, lineContacts(lines), 2.9);
  double bentBefore = 0.0;
  for (const StructureLine& l : lines) {
    const Points P = along(l, 201);
    s->field.setLineCorrection(correction);
    const Weights W = s->field.weightsAt(P);
    for (Index k = 0; k < P.rows(); ++k) {
      const double t = double(k) / double(P.rows() - 1);
      EXPECT_LE((W.row(k) - (1 - t) * W.row(0) - t * W.row(P.rows() - 1)).cwiseAbs().maxCoeff(), 1e-13);
    }
    s->field.setLineCorrection(nullptr);
    const Weights B = s->field.weightsAt(P);
    for (Index k = 0; k < P.rows(); ++k) {
      const double t = double(k) / double(P.rows() - 1);
      bentBefore = std::max(bentBefore, (B.row(k) - (1 - t) * B.row(0) - t * B.row(P.rows() - 1)).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_GT(bentBefore, 1e-4) << "the plain field is already linear along the lines: the check above cannot fail";
  s->field.setLineCorrection(correction);
  const Weights W = s->field.weightsAt(probe);
  EXPECT_LE((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
  EXPECT_LE((W * s->cage.C - probe).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT((W - plain).cwiseAbs().maxCoeff(), 1e-4);  // the correction does something off the lines
}

TEST(LineCorrection, MeetingLinesAgreeAndParallelLinesStayParallel) {
  auto s = squareField();
  const std::vector<StructureLine> lines = drawnLines();
  s->field.setLineCorrection(std::make_shared<LineCorrection>(s->cage, lines, lineContacts(lines), 2.9));
  // The X's crossing: each line's own linear weights, evaluated from its ends, agree there.
  Points ends(4, 2);
  ends << 10, 10, 40, 40, 10, 40, 40, 10;
  const Weights E = s->field.weightsAt(ends);
  const Eigen::RowVectorXd first = 0.5 * (E.row(0) + E.row(1)), second = 0.5 * (E.row(2) + E.row(3));
  EXPECT_LE((first - second).cwiseAbs().maxCoeff(), 1e-13);
  // The pair: under any translation of the controls their images stay parallel.
  const Points P = (Points(4, 2) << lines[3].a.transpose(), lines[3].b.transpose(), lines[4].a.transpose(),
                    lines[4].b.transpose()).finished();
  const Weights W = s->field.weightsAt(P);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-40, 40);
  for (int trial = 0; trial < 20; ++trial) {
    Points T(4, 2);
    for (Index i = 0; i < 4; ++i) T.row(i) << u(rng), u(rng);
    const Points Y = P + W * T;
    const Vec2 d0 = (Y.row(1) - Y.row(0)).transpose(), d1 = (Y.row(3) - Y.row(2)).transpose();
    const double angle = std::abs(std::atan2(d0.x() * d1.y() - d0.y() * d1.x(), d0.dot(d1))) * 180.0 / std::numbers::pi;
    EXPECT_LE(angle, 1e-9) << "trial " << trial;
  }
}

TEST(LineCorrection, TheCageAndWhatLiesOutsideAreNotChanged) {
  auto s = squareField();
  const std::vector<StructureLine> lines = drawnLines();
  Points P(8, 2);  // the corners, points on the edges (the right one next to the line ending 1 px from it), outside
  P << 0, 0, kSquareSide, kSquareSide, kSquareSide, 25, kSquareSide, 30, 30, 0, 0, 45, kSquareSide + 1.0, 25, -3, 20;
  const Weights before = s->field.weightsAt(P);
  s->field.setLineCorrection(std::make_shared<LineCorrection>(s->cage, lines, lineContacts(lines), 2.9));
  EXPECT_TRUE(s->field.weightsAt(P) == before);
}

TEST(LineCorrection, OperatorsAndGradientsAreTheFields) {
  auto s = squareField();
  const std::vector<StructureLine> lines = drawnLines();
  s->field.setLineCorrection(std::make_shared<LineCorrection>(s->cage, lines, lineContacts(lines), 2.9));
  Points P = test::randomPointsIn(200, 1.0, kSquareSide - 1.0, 4);
  P.row(0) << 25.0, 25.0;  // the X's crossing
  P.row(1) << 20.0, 20.0;  // on a line
  const Weights W = s->field.weightsAt(P);
  const Weights viaE = s->field.evaluationOperator(P) * s->field.coefficients();
  EXPECT_LE((viaE - W).cwiseAbs().maxCoeff(), 1e-12);
  Weights gx, gy;
  s->field.gradientsAt(P, gx, gy);
  SparseRowMatrix Ex, Ey;
  s->field.gradientOperators(P, Ex, Ey);
  EXPECT_LE((Ex * s->field.coefficients() - gx).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((Ey * s->field.coefficients() - gy).cwiseAbs().maxCoeff(), 1e-12);
  // Central differences of the weights (their error grows as 1/d³ at a distance d from a line: the
  // points closer than 0.5 px are left out).
  const double h = 1e-4;
  const Points dx = (Points(1, 2) << h, 0).finished().replicate(P.rows(), 1);
  const Points dy = (Points(1, 2) << 0, h).finished().replicate(P.rows(), 1);
  const Weights fx = (s->field.weightsAt(P + dx) - s->field.weightsAt(P - dx)) / (2 * h);
  const Weights fy = (s->field.weightsAt(P + dy) - s->field.weightsAt(P - dy)) / (2 * h);
  for (Index k = 2; k < P.rows(); ++k) {
    double nearest = 1e9;
    for (const StructureLine& l : lines) nearest = std::min(nearest, pointSegmentDistance(P.row(k).transpose(), l.a, l.b));
    if (nearest < 0.5) continue;
    EXPECT_LE((fx.row(k) - gx.row(k)).cwiseAbs().maxCoeff(), 1e-5) << "at " << P.row(k);
    EXPECT_LE((fy.row(k) - gy.row(k)).cwiseAbs().maxCoeff(), 1e-5) << "at " << P.row(k);
  }
}

TEST(LineCorrection, RefusesWhatItCannotCorrect) {
  auto s = squareField();
  std::vector<StructureLine> lines = {{{10, 10}, {10, 10}, -1}};
  EXPECT_THROW(LineCorrection(s->cage, lines, {}, 2.9), std::invalid_argument);
  lines = {{{10, 10}, {20, 20}, -1}};
  EXPECT_THROW(LineCorrection(s->cage, lines, {}, 0.0), std::invalid_argument);
  Cage open = s->cage;
  open.closed = false;
  open.edges = {{0, 1}, {1, 2}};
  EXPECT_THROW(LineCorrection(open, lines, {}, 2.9), std::invalid_argument);
}

}  // namespace
}  // namespace kc
