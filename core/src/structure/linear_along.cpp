#include "kc/core/structure/linear_along.h"

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "kc/core/cage.h"

namespace kc {
namespace {

/// Fit points of one segment at spacing ≤ step, ends included, with their targets.
void fitPoints(const LinearSegment& s, double step, Points& P, Weights& target) {
  const Index n = std::max<Index>(2, static_cast<Index>(std::ceil((s.b - s.a).norm() / step)) + 1);
  P.resize(n, 2);
  target.resize(n, s.wa.size());
  for (Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / static_cast<double>(n - 1);
    P.row(k) = ((1.0 - t) * s.a + t * s.b).transpose();
    target.row(k) = (1.0 - t) * s.wa + t * s.wb;
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
  // The kernel's width along each segment (σ when constant), at 65 points: the fit points and the
  // scaling of the polynomial rows follow its smallest value, the reach of the correction its
  // largest (where the width is larger, fewer samples lie within a given distance).
  std::vector<double> segmentSigma(segments.size(), kernel.sigma), segmentReach(segments.size(), kernel.sigma);
  if (kernel.variable())
    for (std::size_t s = 0; s < segments.size(); ++s) {
      double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
      for (int k = 0; k <= 64; ++k) {
        const double w = kernel.widthAt(segments[s].a + (k / 64.0) * (segments[s].b - segments[s].a));
        lo = std::min(lo, w);
        hi = std::max(hi, w);
      }
      segmentSigma[s] = lo;
      segmentReach[s] = hi;
    }
  const Eigen::VectorXd widthX = kernel.widthsAt(X);

  // All fit points, their segment and their targets; e = w(F) − target, kept up to date.
  std::vector<Points> P(segments.size());
  std::vector<Weights> T(segments.size());
  Index total = 0;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (segments[s].wa.size() != m || segments[s].wb.size() != m) throw std::invalid_argument("makeLinearAlong: end weights need m entries");
    fitPoints(segments[s], options.fitSpacing * segmentSigma[s], P[s], T[s]);
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
  Weights e = field.weightsAt(F) - target;
  const Eigen::VectorXd widthF = kernel.widthsAt(F);
  report.before = e.cwiseAbs().maxCoeff();

  std::vector<Index> keptRows;  // their rows are put back exactly at the end
  for (Index i = 0; i < n; ++i)
    if (keep[std::size_t(i)]) keptRows.push_back(i);
  const Weights kept = W(keptRows, Eigen::all);
  std::vector<char> changed(static_cast<std::size_t>(n), 0), adjusted(static_cast<std::size_t>(n), 0);
  for (int sweep = 0; sweep < std::max(1, options.sweeps); ++sweep)
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Vec2 a = segments[s].a, b = segments[s].b;
    const double sigma = segmentSigma[s], radius = options.reach * segmentReach[s];
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
      kernelRow(r, F.row(q), widthF(q), 1.0);
      rhs.row(r++) = -e.row(q);
    }
    for (Index i : onLine) kernelRow(r++, X.row(i), widthX(i), 1.0);  // their rows are the linear targets already: no change
    const double w = options.holdWeight;
    for (Index i : held) kernelRow(r++, X.row(i), widthX(i), w);
    for (Index q : others) kernelRow(r++, F.row(q), widthF(q), w);
    for (Index i : loose) kernelRow(r++, X.row(i), widthX(i), options.freeWeight);
    if (exact) {
      for (Index c = 0; c < cols; ++c) {
        A(r, c) = w;
        A(r + 1, c) = w * X(nodes[std::size_t(c)], 0) / sigma;  // scaled like the kernel rows
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
