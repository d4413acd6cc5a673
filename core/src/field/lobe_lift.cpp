#include "kc/core/field/lobe_lift.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>

#include <Eigen/Dense>

#include "kc/core/weights/optimizer.h"

namespace kc {

namespace {

constexpr Index kP = KernelField::kPolynomialNodes;
/// Points this close to the cage (× the local spacing) count as on it, from either side.
constexpr double kOnCage = 0.02;
/// A bump the control points' pins leave with less than this share of its free gain at its lobe
/// is not used: lobes within a spacing or two of another control point (3-5% there), whose lift
/// rings into a hump of its control 2-3 spacings away, across a notch into the other side
/// (docs/notes/measured-constants.md).
constexpr double kPinnedGain = 0.05;
/// How far a lift changes the field, in spacings at its lobe (its bump's kernels, 3σ ≈ 3T).
constexpr double kReach = 4.0;

struct Candidate {
  Vec2 y;
  Index control = 0;
  double value = 0.0;
  double spacing = 0.0;  ///< The local sample spacing at y.
};

double rowDot(const SparseRowMatrix& E, Index row, const RowMatrix& Coef, Index column) {
  double v = 0.0;
  for (SparseRowMatrix::InnerIterator it(E, row); it; ++it) v += it.value() * Coef(it.col(), column);
  return v;
}

/// Keeps the deepest candidate of each control within `radius` × its spacing of a deeper one.
std::vector<Candidate> deepestApart(std::vector<Candidate> c, double radius) {
  std::sort(c.begin(), c.end(), [](const Candidate& a, const Candidate& b) { return a.value < b.value; });
  std::vector<Candidate> kept;
  for (const Candidate& k : c) {
    const bool near = std::any_of(kept.begin(), kept.end(), [&](const Candidate& o) {
      return o.control == k.control && (o.y - k.y).norm() < radius * std::max(o.spacing, k.spacing);
    });
    if (!near) kept.push_back(k);
  }
  return kept;
}

/// Moves each candidate to the deepest point of its control's weight nearby (pattern search:
/// eight neighbours at radius r, r halved when none is deeper), staying inside the cage.
void descend(const KernelField& field, const CageQueries& cage, std::vector<Candidate>& c) {
  const RowMatrix Coef = field.coefficients();
  std::vector<double> r(c.size());
  for (std::size_t k = 0; k < c.size(); ++k) r[k] = 0.25 * c[k].spacing;
  constexpr int kSteps = 10, kDirections = 8;
  for (int step = 0; step < kSteps; ++step) {
    Points P(static_cast<Index>(c.size()) * kDirections, 2);
    std::vector<char> valid(static_cast<std::size_t>(P.rows()));
    for (std::size_t k = 0; k < c.size(); ++k)
      for (int d = 0; d < kDirections; ++d) {
        const double a = 2.0 * std::numbers::pi * d / kDirections;
        const Vec2 p = c[k].y + r[k] * Vec2(std::cos(a), std::sin(a));
        const Index row = static_cast<Index>(k) * kDirections + d;
        P.row(row) = p;
        valid[static_cast<std::size_t>(row)] = cage.inside(p) || cage.distance(p) <= kOnCage * c[k].spacing;
      }
    const SparseRowMatrix E = field.evaluationOperator(P);
    for (std::size_t k = 0; k < c.size(); ++k) {
      Index best = -1;
      double bestValue = c[k].value;
      for (int d = 0; d < kDirections; ++d) {
        const Index row = static_cast<Index>(k) * kDirections + d;
        if (!valid[static_cast<std::size_t>(row)]) continue;
        const double v = rowDot(E, row, Coef, c[k].control);
        if (v < bestValue) bestValue = v, best = row;
      }
      if (best >= 0) {
        c[k].y = P.row(best);
        c[k].value = bestValue;
      } else {
        r[k] *= 0.5;
      }
    }
  }
}

/// A lobe's bump on the samples: coefficients c (sample, value) with k(x)ᵀc the bump's shape,
/// zero at every control point (the Lagrange property, thesis 3.18: w(c_i) = e_i stays exact).
struct Bump {
  std::vector<std::pair<Index, double>> c;
  double gain = 0.0;  ///< The bump's value at its lobe's deepest point, E(y)·c.
  double free = 0.0;  ///< The same without the pins, |E(y)|² over the samples.
};

/// The kernel row of y itself, E(y) restricted to the samples, made orthogonal to the rows of the
/// control points that reach it (E(c_p)·c = 0).
Bump bumpFor(const SparseRowMatrix& E, Index row, const SparseRowMatrix& EC) {
  Bump b;
  std::vector<Index> at;
  Eigen::VectorXd e;
  {
    std::vector<double> v;
    for (SparseRowMatrix::InnerIterator it(E, row); it; ++it)
      if (it.col() >= kP) at.push_back(it.col()), v.push_back(it.value());
    e = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Index>(v.size()));
  }
  std::vector<Eigen::VectorXd> pins;
  for (Index p = 0; p < EC.rows(); ++p) {
    Eigen::VectorXd a = Eigen::VectorXd::Zero(e.size());
    bool reaches = false;
    for (SparseRowMatrix::InnerIterator it(EC, p); it; ++it) {
      const auto k = std::lower_bound(at.begin(), at.end(), it.col());
      if (k != at.end() && *k == it.col()) a(k - at.begin()) = it.value(), reaches = true;
    }
    if (reaches) pins.push_back(a);
  }
  Eigen::VectorXd c = e;
  if (!pins.empty()) {
    Eigen::MatrixXd A(static_cast<Index>(pins.size()), e.size());
    for (std::size_t k = 0; k < pins.size(); ++k) A.row(static_cast<Index>(k)) = pins[k].transpose();
    c -= A.transpose() * A.transpose().completeOrthogonalDecomposition().solve(c);
  }
  b.gain = e.dot(c);
  b.free = e.squaredNorm();
  for (std::size_t k = 0; k < at.size(); ++k)
    if (c(static_cast<Index>(k)) != 0.0) b.c.emplace_back(at[k] - kP, c(static_cast<Index>(k)));
  return b;
}

/// The lift of one round for the lobes' deepest points `lobes` (Kaczmarz passes over them).
RowMatrix liftFor(const KernelField& field, const std::vector<Candidate>& lobes, const LobeLiftOptions& o) {
  const Points& X = field.interpolator().samples();
  const Index m = field.controls(), n = X.rows();
  const Points C = X.topRows(m);
  const double L = std::max((C.colwise().maxCoeff() - C.colwise().minCoeff()).maxCoeff(), 1.0);
  Points Y(static_cast<Index>(lobes.size()), 2);
  for (std::size_t l = 0; l < lobes.size(); ++l) Y.row(static_cast<Index>(l)) = lobes[l].y;
  const SparseRowMatrix E = field.evaluationOperator(Y), EC = field.evaluationOperator(C);
  const Weights base = field.unboundedWeightsAt(Y);
  // The lobes a bump can raise: a lobe pinned by control points all round is left as it is.
  std::vector<std::pair<Index, Bump>> liftable;
  for (Index l = 0; l < Y.rows(); ++l)
    if (Bump b = bumpFor(E, l, EC); b.gain > kPinnedGain * b.free) liftable.emplace_back(l, std::move(b));

  RowMatrix dU = RowMatrix::Zero(n, m);
  Eigen::VectorXd w(m), a(m), d(m);
  std::vector<Eigen::Vector3d> g(static_cast<std::size_t>(m));
  constexpr int kPasses = 3;
  for (int pass = 0; pass < kPasses; ++pass)
    for (const auto& [l, bump] : liftable) {
      const Index j = lobes[static_cast<std::size_t>(l)].control;
      const Vec2 y = lobes[static_cast<std::size_t>(l)].y;
      w = base.row(l).transpose();
      for (SparseRowMatrix::InnerIterator it(E, l); it; ++it)
        if (it.col() >= kP) w += it.value() * dU.row(it.col() - kP).transpose();
      const double deficit = o.target - w(j);
      if (deficit <= 0.0) continue;
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      for (Index c = 0; c < m; ++c) {
        g[static_cast<std::size_t>(c)] = Eigen::Vector3d(1.0, (C(c, 0) - y.x()) / L, (C(c, 1) - y.y()) / L);
        a(c) = allowanceOf(w(c), o.allowance);
        M += a(c) * g[static_cast<std::size_t>(c)] * g[static_cast<std::size_t>(c)].transpose();
      }
      const Eigen::Vector3d z = M.ldlt().solve(g[static_cast<std::size_t>(j)]);
      for (Index c = 0; c < m; ++c) d(c) = (c == j ? 1.0 : 0.0) - a(c) * g[static_cast<std::size_t>(c)].dot(z);
      if (d(j) <= 1e-6) continue;
      const double t = deficit / (bump.gain * d(j));
      for (const auto& [i, ci] : bump.c) dU.row(i) += (t * ci) * d.transpose();
    }
  return dU;
}

}  // namespace

LobeLiftReport liftLobes(KernelField& field, const Cage& cage, const std::vector<SampleKind>& kinds, const LobeLiftOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  LobeLiftReport report;
  const Points& X = field.interpolator().samples();
  const GaussianKernel& kernel = field.interpolator().kernel();
  const Index m = field.controls();
  const CageQueries queries(cage);

  // Probes: six around every sample inside the cage, half a spacing out (turned by the golden
  // angle from one sample to the next, so the probes do not line up).
  Points P(6 * X.rows(), 2);
  std::vector<double> spacing;
  Index count = 0;
  for (Index i = 0; i < X.rows(); ++i) {
    if (kinds[static_cast<std::size_t>(i)] == SampleKind::Exterior) continue;
    const Vec2 x = X.row(i);
    const double T = kernel.widthAt(x) * std::numbers::pi / 3.0;  // σ = 3T/π (thesis 3.28)
    for (int k = 0; k < 6; ++k) {
      const double a = k * std::numbers::pi / 3.0 + 2.399963 * static_cast<double>(i);
      const Vec2 p = x + 0.5 * T * Vec2(std::cos(a), std::sin(a));
      if (!queries.inside(p)) continue;
      P.row(count++) = p;
      spacing.push_back(T);
    }
  }
  // And along the cage's loop edges, where the hat functions kink at the vertices: on the edge and
  // 0.15 and 0.35 spacings inside, a quarter spacing apart.
  std::vector<Vec2> edgeProbes;
  for (const auto& e : loopEdges(cage)) {
    const Vec2 a = cage.C.row(e[0]), b = cage.C.row(e[1]);
    const double length = (b - a).norm();
    const Vec2 normal = Vec2(a.y() - b.y(), b.x() - a.x()) / length;
    double t = 0.0;
    while (true) {
      const Vec2 x = a + t * (b - a);
      const double T = kernel.widthAt(x) * std::numbers::pi / 3.0;
      t += 0.25 * T / length;
      if (t >= 1.0) break;
      const Vec2 q = a + t * (b - a);
      const double side = queries.inside(q + 1e-3 * T * normal) ? 1.0 : -1.0;
      for (const double depth : {1e-3, 0.15, 0.35}) {
        const Vec2 p = q + side * depth * T * normal;
        if (!queries.inside(p)) continue;
        edgeProbes.push_back(p);
        spacing.push_back(T);
      }
    }
  }
  P.conservativeResize(count + static_cast<Index>(edgeProbes.size()), 2);
  for (const Vec2& p : edgeProbes) P.row(count++) = p;

  // Each round re-probes only where the last one lifted (a bump reaches a few spacings).
  std::vector<Index> active(static_cast<std::size_t>(P.rows()));
  std::iota(active.begin(), active.end(), Index(0));
  std::vector<double> lowest(static_cast<std::size_t>(P.rows()), 0.0);
  for (int round = 0; round <= o.rounds && !active.empty(); ++round) {
    Points Q(static_cast<Index>(active.size()), 2);
    for (std::size_t k = 0; k < active.size(); ++k) Q.row(static_cast<Index>(k)) = P.row(active[k]);
    const Weights W = field.unboundedWeightsAt(Q);
    std::vector<Candidate> c;
    for (Index q = 0; q < W.rows(); ++q) {
      const Index p = active[static_cast<std::size_t>(q)];
      lowest[static_cast<std::size_t>(p)] = W.row(q).minCoeff();
      for (Index j = 0; j < m; ++j)
        if (W(q, j) < -o.trigger) c.push_back({P.row(p), j, W(q, j), spacing[static_cast<std::size_t>(p)]});
    }
    const double deepest = *std::min_element(lowest.begin(), lowest.end());
    if (round == 0) report.deepestBefore = deepest;
    report.deepestAfter = deepest;
    if (round == o.rounds || c.empty()) break;
    c = deepestApart(std::move(c), 1.0);
    descend(field, queries, c);
    c = deepestApart(std::move(c), 0.25);
    field.addLift(liftFor(field, c, o));
    report.lobes += static_cast<Index>(c.size());
    report.rounds = round + 1;
    active.clear();
    for (Index p = 0; p < P.rows(); ++p) {
      const Vec2 x = P.row(p);
      if (std::any_of(c.begin(), c.end(), [&](const Candidate& l) { return (x - l.y).norm() < kReach * l.spacing; }))
        active.push_back(p);
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace kc
