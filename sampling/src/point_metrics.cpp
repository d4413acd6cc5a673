#include "kc/sampling/point_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "kc/core/parallel.h"
#include "kc/core/spatial_grid.h"

namespace kc::sampling {
namespace {

/// Typical spacing of X: sqrt(bounding-box area / n).
double typicalSpacing(const Points& X) {
  const double w = X.col(0).maxCoeff() - X.col(0).minCoeff(), h = X.col(1).maxCoeff() - X.col(1).minCoeff();
  const double area = std::max(w * h, std::max(w, h) * std::max(w, h) * 1e-6);
  return std::max(std::sqrt(area / static_cast<double>(X.rows())), 1e-12);
}

/// Distance from x to the nearest row of X other than `self`, searching with growing radii.
double nearestDistance(const SpatialGrid& grid, const Vec2& x, Index self, double r0, double rMax) {
  for (double r = r0;; r *= 2.0) {
    double best2 = std::numeric_limits<double>::infinity();
    grid.forEachWithin(x, r, [&](Index j, double d2) {
      if (j != self) best2 = std::min(best2, d2);
    });
    if (best2 < std::numeric_limits<double>::infinity()) return std::sqrt(best2);
    if (r > rMax) return std::numeric_limits<double>::infinity();
  }
}

}  // namespace

Eigen::VectorXd nearestNeighbourDistances(const Points& X) {
  const Index n = X.rows();
  Eigen::VectorXd d = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  if (n < 2) return d;
  const double t = typicalSpacing(X);
  const SpatialGrid grid(X, t);
  const double rMax = 4.0 * (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm() + t;
  parallelFor(n, [&](Index i) { d(i) = nearestDistance(grid, X.row(i), i, t, rMax); }, 512);
  return d;
}

double meanNearestNeighbourSpacing(const Points& X) {
  if (X.rows() < 2) return 0.0;
  return nearestNeighbourDistances(X).mean();
}

double minimumDistance(const Points& X, Index first) {
  const Eigen::VectorXd d = nearestNeighbourDistances(X);
  return first < X.rows() ? d.tail(X.rows() - first).minCoeff() : std::numeric_limits<double>::infinity();
}

double fillDistance(const Points& X, const Rect& domain, double probe) {
  if (X.rows() == 0 || !(probe > 0.0)) return std::numeric_limits<double>::infinity();
  const Index nx = static_cast<Index>(std::floor(domain.width() / probe)) + 1;
  const Index ny = static_cast<Index>(std::floor(domain.height() / probe)) + 1;
  const double t = typicalSpacing(X);
  const SpatialGrid grid(X, t);
  const double rMax = 4.0 * std::hypot(domain.width(), domain.height()) + t;
  Eigen::VectorXd rowMax(ny);
  parallelFor(ny, [&](Index j) {
    double m = 0.0;
    for (Index i = 0; i < nx; ++i) {
      const Vec2 p(std::min(domain.x0 + i * probe, domain.x1), std::min(domain.y0 + j * probe, domain.y1));
      m = std::max(m, nearestDistance(grid, p, -1, t, rMax));
    }
    rowMax(j) = m;
  }, 4);
  return rowMax.maxCoeff();
}

PointSetMetrics pointSetMetrics(const Points& X, double h, const Rect& domain, Index first, double probe) {
  PointSetMetrics m;
  const Eigen::VectorXd d = nearestNeighbourDistances(X);
  if (first < X.rows()) {
    const Eigen::VectorXd t = d.tail(X.rows() - first);
    m.separation = t.minCoeff() / h;
    m.nnMean = t.mean() / h;
    m.nnCv = std::sqrt((t.array() - t.mean()).square().mean()) / t.mean();
  }
  m.fill = fillDistance(X, domain, probe > 0.0 ? probe : h / 8.0) / h;
  return m;
}

PointSetMetrics gradedPointSetMetrics(const Points& X, const SizingField& sizing, const Rect& domain, Index first) {
  PointSetMetrics m;
  const Eigen::VectorXd d = nearestNeighbourDistances(X), h = sizing.at(X);
  if (first < X.rows()) {
    const Index n = X.rows() - first;
    const Eigen::ArrayXd t = d.tail(n).array() / h.tail(n).array();
    m.separation = t.minCoeff();
    m.nnMean = t.mean();
    m.nnCv = std::sqrt((t - t.mean()).square().mean()) / t.mean();
  }
  // Probes at the centres of cells split until their side is at most h(centre)/8.
  std::vector<Vec2> probes;
  auto visit = [&](auto&& self, double x0, double y0, double side) -> void {
    const Vec2 c(x0 + 0.5 * side, y0 + 0.5 * side);
    if (side > sizing(c) / 8.0) {
      const double s2 = 0.5 * side;
      for (int k = 0; k < 4; ++k) self(self, x0 + (k % 2) * s2, y0 + (k / 2) * s2, s2);
      return;
    }
    if (domain.contains(c)) probes.push_back(c);
  };
  const double root = sizing.hMax();
  for (double y = domain.y0; y < domain.y1; y += root)
    for (double x = domain.x0; x < domain.x1; x += root) visit(visit, x, y, root);
  const SpatialGrid grid(X, root);
  std::vector<double> worst(probes.size(), 0.0);
  parallelFor(static_cast<Index>(probes.size()), [&](Index k) {
    const Vec2& p = probes[static_cast<std::size_t>(k)];
    const double hp = sizing(p), reach = 2.0 * hp;
    double best = reach * reach;
    grid.forEachWithin(p, reach, [&](Index, double d2) { best = std::min(best, d2); });
    worst[static_cast<std::size_t>(k)] = std::sqrt(best) / hp;
  });
  for (double w : worst) m.fill = std::max(m.fill, w);
  return m;
}

RadialSpectrum radialPowerSpectrum(const Points& X, const RadialSpectrumOptions& options) {
  RadialSpectrum s;
  const Index n = X.rows();
  const int bins = std::max(1, options.bins), dirs = std::max(1, options.directions);
  s.omega.resize(bins);
  s.power.setZero(bins);
  if (n < 2) return s;
  const double T = meanNearestNeighbourSpacing(X);
  const double omegaMax = options.omegaMax > 0.0 ? options.omegaMax : 3.0 * 2.0 * std::numbers::pi / T;
  for (int b = 0; b < bins; ++b) s.omega(b) = omegaMax * (b + 1) / bins;

  // Hann window over the bounding box.
  const Eigen::RowVector2d lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  Eigen::VectorXd w(n);
  for (Index j = 0; j < n; ++j) {
    double v = 1.0;
    for (int c = 0; c < 2; ++c) {
      const double ext = hi(c) - lo(c);
      const double u = ext > 0.0 ? (X(j, c) - lo(c)) / ext : 0.5;
      v *= std::sin(std::numbers::pi * u) * std::sin(std::numbers::pi * u);
    }
    w(j) = v;
  }
  const double norm = w.squaredNorm();
  const Eigen::RowVector2d centre = 0.5 * (lo + hi);
  parallelFor(bins, [&](Index b) {
    double acc = 0.0;
    for (int d = 0; d < dirs; ++d) {
      const double a = std::numbers::pi * d / dirs;
      const double ox = s.omega(b) * std::cos(a), oy = s.omega(b) * std::sin(a);
      double re = 0.0, im = 0.0;
      for (Index j = 0; j < n; ++j) {
        const double phase = ox * (X(j, 0) - centre(0)) + oy * (X(j, 1) - centre(1));
        re += w(j) * std::cos(phase);
        im -= w(j) * std::sin(phase);
      }
      acc += re * re + im * im;
    }
    s.power(b) = norm > 0.0 ? acc / (dirs * norm) : 0.0;
  }, 1);
  return s;
}

}  // namespace kc::sampling
