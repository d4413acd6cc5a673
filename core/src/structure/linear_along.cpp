#include "kc/core/structure/linear_along.h"

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "kc/core/cage.h"

namespace kc {
namespace {

/// Parameters 0 = t_0 < … < t_n = 1 of the fit points of segment a → b, spaced by about step·σ(p)
/// where the kernel's width is σ(p): n = ⌈∫ ds / (step·σ)⌉ intervals, equal in that measure. A
/// constant width gives n = ⌈|b − a| / (step·σ)⌉ equal intervals, t_k = k/n. A graded width puts
/// dense fit points only where it is small (a crossing, a narrow place), so that the fit costs
/// what the segment's local widths need rather than its smallest width everywhere.
std::vector<double> fitParameters(const Vec2& a, const Vec2& b, const GaussianKernel& kernel, double step) {
  const double length = (b - a).norm();
  std::vector<double> t;
  if (!kernel.variable() || length == 0.0) {
    const Index n = std::max<Index>(1, static_cast<Index>(std::ceil(length / (step * kernel.sigma))));
    for (Index k = 0; k <= n; ++k) t.push_back(static_cast<double>(k) / static_cast<double>(n));
    return t;
  }
  // u(t) = ∫_0^t |b − a| / (step·σ) dt, tabulated in quarter fit steps (|∇σ| ≤ ~0.4: σ changes by
  // at most 10% over one) by the trapezoid rule on 1/σ, then inverted at u = k·u(1)/n.
  std::vector<double> tt{0.0}, uu{0.0};
  double sa = kernel.widthAt(a);
  while (tt.back() < 1.0) {
    const double t1 = std::min(1.0, tt.back() + 0.25 * step * sa / length);
    const double sb = kernel.widthAt(a + t1 * (b - a));
    uu.push_back(uu.back() + 0.5 * (t1 - tt.back()) * length / step * (1.0 / sa + 1.0 / sb));
    tt.push_back(t1);
    sa = sb;
  }
  const Index n = std::max<Index>(1, static_cast<Index>(std::ceil(uu.back() - 1e-9)));
  t.push_back(0.0);
  for (Index k = 1, j = 1; k < n; ++k) {
    const double u = uu.back() * static_cast<double>(k) / static_cast<double>(n);
    while (uu[std::size_t(j)] < u) ++j;
    const double f = (u - uu[std::size_t(j) - 1]) / (uu[std::size_t(j)] - uu[std::size_t(j) - 1]);
    t.push_back(tt[std::size_t(j) - 1] + f * (tt[std::size_t(j)] - tt[std::size_t(j) - 1]));
  }
  t.push_back(1.0);
  return t;
}

/// Fit points of one segment at parameters t, with their targets (1 − t)·wa + t·wb.
void fitPoints(const LinearSegment& s, const std::vector<double>& t, Points& P, Weights& target) {
  const Index n = static_cast<Index>(t.size());
  P.resize(n, 2);
  target.resize(n, s.wa.size());
  for (Index k = 0; k < n; ++k) {
    const double tk = t[std::size_t(k)];
    P.row(k) = ((1.0 - tk) * s.a + tk * s.b).transpose();
    target.row(k) = (1.0 - tk) * s.wa + tk * s.wb;
  }
}

}  // namespace

LinearityReport makeLinearAlong(KernelField& field, std::span<const LinearSegment> segments, const std::vector<char>& keep,
                                Weights& W, const LinearityOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  LinearityReport report;
  if (segments.empty()) return report;
  const KernelInterpolator& interp = field.interpolator();
  const Points& X = interp.samples();
  const GaussianKernel& kernel = interp.kernel();
  const Index n = X.rows(), m = W.cols();
  if (W.rows() != n || static_cast<Index>(keep.size()) != n) throw std::invalid_argument("makeLinearAlong: W and keep need one row per sample");
  const bool exact = interp.mode() == InterpMode::Exact;
  const double theta = kernel.cutoff();
  // All fit points, their segment and their targets; e = w(F) − target, kept up to date.
  std::vector<Points> P(segments.size());
  std::vector<Weights> T(segments.size());
  Index total = 0;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (segments[s].wa.size() != m || segments[s].wb.size() != m) throw std::invalid_argument("makeLinearAlong: end weights need m entries");
    fitPoints(segments[s], fitParameters(segments[s].a, segments[s].b, kernel, options.fitSpacing), P[s], T[s]);
    total += P[s].rows();
  }
  Points F(total, 2);
  Weights target(total, m);
  std::vector<std::size_t> owner(static_cast<std::size_t>(total));
  for (std::size_t s = 0, at = 0; s < segments.size(); ++s) {
    F.middleRows(Index(at), P[s].rows()) = P[s];
    target.middleRows(Index(at), P[s].rows()) = T[s];
    for (Index k = 0; k < P[s].rows(); ++k) owner[at + std::size_t(k)] = s;
    at += std::size_t(P[s].rows());
  }
  const Eigen::VectorXd widthX = kernel.widthsAt(X), widthF = kernel.widthsAt(F);
  // The width along each segment (σ when constant), over its fit points (≤ 10% apart in width): the
  // reach of the correction and the scaling of the polynomial rows follow its largest value (where
  // the width is larger, fewer samples lie within a given distance). A fit point's row weighs
  // √(σ(p)/σ_min), σ_min the smallest width on its segment: the fit point stands for a piece of
  // the segment σ(p)/σ_min times as long as one at σ_min, so the least-squares objective is the
  // quadrature of the squared misfit along the segment, the same as with fit points every
  // fitSpacing·σ_min (1 for a constant width).
  std::vector<double> segmentMin(segments.size(), kernel.sigma), segmentMax(segments.size(), kernel.sigma);
  Eigen::VectorXd fitWeight = Eigen::VectorXd::Ones(total);
  if (kernel.variable()) {
    std::fill(segmentMin.begin(), segmentMin.end(), std::numeric_limits<double>::infinity());
    std::fill(segmentMax.begin(), segmentMax.end(), 0.0);
    for (Index q = 0; q < total; ++q) {
      const std::size_t s = owner[std::size_t(q)];
      segmentMin[s] = std::min(segmentMin[s], widthF(q));
      segmentMax[s] = std::max(segmentMax[s], widthF(q));
    }
    for (Index q = 0; q < total; ++q) fitWeight(q) = std::sqrt(widthF(q) / segmentMin[owner[std::size_t(q)]]);
  }
  report.fitPoints = total;
  Weights e = field.weightsAt(F) - target;
  report.before = e.cwiseAbs().maxCoeff();

  std::vector<Index> keptRows;  // their rows are put back exactly at the end
  for (Index i = 0; i < n; ++i)
    if (keep[std::size_t(i)]) keptRows.push_back(i);
  const Weights kept = W(keptRows, Eigen::all);
  std::vector<char> changed(static_cast<std::size_t>(n), 0), adjusted(static_cast<std::size_t>(n), 0);
  for (int sweep = 0; sweep < std::max(1, options.sweeps); ++sweep)
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Vec2 a = segments[s].a, b = segments[s].b;
    const double sigma = segmentMax[s], radius = options.reach * segmentMax[s];
    std::vector<Index> nodes, held, onLine, own, others, loose;  // onLine: held samples on the segment (fit, not held)
    for (Index j = 0; j < n; ++j) {
      const double d = pointSegmentDistance(X.row(j), a, b);
      if (d <= radius) nodes.push_back(j);
      if (d > radius + theta) continue;
      if (keep[std::size_t(j)]) (d <= 1e-9 * (1.0 + X.row(j).cwiseAbs().maxCoeff()) ? onLine : held).push_back(j);
      else if (options.freeWeight > 0.0) loose.push_back(j);
    }
    for (Index q = 0; q < total; ++q) {
      if (owner[std::size_t(q)] == s) own.push_back(q);
      else if (pointSegmentDistance(F.row(q), a, b) <= radius + theta) others.push_back(q);
    }
    if (nodes.empty()) continue;
    // One least-norm least-squares system: the fit rows, then the side conditions weighted by
    // options.holdWeight.
    const Index cols = Index(nodes.size());
    const Index rows = Index(own.size() + onLine.size() + held.size() + others.size() + loose.size()) + (exact ? 3 : 0);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, cols), rhs = Eigen::MatrixXd::Zero(rows, m);
    // k(p, x_node) for p of width sp (the constant kernel ignores the widths).
    auto k = [&](const Vec2& p, double sp, Index node) {
      return kernel((p - Vec2(X.row(node))).squaredNorm(), sp, widthX(node));
    };
    auto kernelRow = [&](Index r, const Vec2& p, double sp, double weight) {
      for (Index c = 0; c < cols; ++c) A(r, c) = weight * k(p, sp, nodes[std::size_t(c)]);
    };
    Index r = 0;
    for (Index q : own) {
      kernelRow(r, F.row(q), widthF(q), fitWeight(q));
      rhs.row(r++) = -fitWeight(q) * e.row(q);
    }
    for (Index i : onLine) kernelRow(r++, X.row(i), widthX(i), 1.0);  // their rows are the linear targets already: no change
    const double w = options.holdWeight;
    for (Index i : held) kernelRow(r++, X.row(i), widthX(i), w);
    for (Index q : others) kernelRow(r++, F.row(q), widthF(q), w * fitWeight(q));
    for (Index i : loose) kernelRow(r++, X.row(i), widthX(i), options.freeWeight);
    if (exact) {
      for (Index c = 0; c < cols; ++c) {
        A(r, c) = w;
        A(r + 1, c) = w * X(nodes[std::size_t(c)], 0) / sigma;  // over the largest width: over the smallest
                                                                  // (0.03 px at a crossing), they dwarfed the fit rows
        A(r + 2, c) = w * X(nodes[std::size_t(c)], 1) / sigma;
      }
    }
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    cod.setThreshold(options.rankTolerance);
    cod.compute(A);
    const Eigen::MatrixXd dU = cod.solve(rhs);  // cols×m

    // W += K(·, N) ΔU for every sample within θ of a node; e likewise at fit points.
    for (Index i = 0; i < n; ++i) {
      if (pointSegmentDistance(X.row(i), a, b) > radius + theta) continue;
      Eigen::RowVectorXd dw = Eigen::RowVectorXd::Zero(m);
      for (Index c = 0; c < cols; ++c) {
        const double kc = k(X.row(i), widthX(i), nodes[std::size_t(c)]);
        if (kc != 0.0) dw += kc * dU.row(c);
      }
      if (dw.cwiseAbs().maxCoeff() > 0.0) {
        W.row(i) += dw;
        changed[std::size_t(i)] = 1;
      }
    }
    for (Index q = 0; q < total; ++q) {
      if (pointSegmentDistance(F.row(q), a, b) > radius + theta) continue;
      for (Index c = 0; c < cols; ++c) {
        const double kc = k(F.row(q), widthF(q), nodes[std::size_t(c)]);
        if (kc != 0.0) e.row(q) += kc * dU.row(c);
      }
    }
    for (Index j : nodes) adjusted[std::size_t(j)] = 1;
  }
  for (std::size_t i = 0; i < changed.size(); ++i) {
    report.changedRows += changed[i];
    report.adjusted += adjusted[i];
  }
  // The held rows moved by about rankTolerance; their exact values back (the field interpolates
  // them: Lagrange and the linear edge samples to round-off), which moves the fit by as little.
  W(keptRows, Eigen::all) = kept;
  field.update(W);
  report.after = (field.weightsAt(F) - target).cwiseAbs().maxCoeff();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace kc
