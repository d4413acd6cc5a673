#include "kc/core/weights/heat_diffusion.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "kc/core/parallel.h"
#include "../sparse_cholesky.h"

namespace kc {
namespace {

using Edge = std::array<int, 2>;

/// Uniform grid over the cage edges: a segment can only cross the cage if it comes within `tol`
/// of an edge bucketed in the cells its bounding box meets; only those pairs pay for the exact
/// (and O(#edges)) kc::segmentCrossesCage.
class EdgeGrid {
 public:
  EdgeGrid(const Cage& cage, const std::vector<Edge>& edges, Vec2 lo, Vec2 hi, double cell, double tol)
      : m_cage(cage), m_edges(edges), m_tol(tol) {
    const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    m_cell = std::max(cell, extent / 512.0);  // at most ~512² cells
    m_lo = lo;
    m_nx = static_cast<int>((hi.x() - lo.x()) / m_cell) + 1;
    m_ny = static_cast<int>((hi.y() - lo.y()) / m_cell) + 1;
    m_cells.assign(static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny), {});
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const Vec2 a = cage.C.row(edges[e][0]), b = cage.C.row(edges[e][1]);
      forCells(a.cwiseMin(b), a.cwiseMax(b), [&](std::size_t c) { m_cells[c].push_back(static_cast<int>(e)); });
    }
  }

  /// Exact: true when the segment a–b crosses the cage (kc::segmentCrossesCage).
  bool crosses(const Vec2& a, const Vec2& b) const {
    bool near = false;
    forCells(a.cwiseMin(b), a.cwiseMax(b), [&](std::size_t c) {
      for (int e : m_cells[c]) {
        if (near) return;
        const Vec2 p = m_cage.C.row(m_edges[static_cast<std::size_t>(e)][0]);
        const Vec2 q = m_cage.C.row(m_edges[static_cast<std::size_t>(e)][1]);
        if (segmentSegmentDistance(a, b, p, q) <= m_tol) near = true;
      }
    });
    return near && segmentCrossesCage(m_cage, a, b);
  }

 private:
  template <class F>
  void forCells(const Vec2& lo, const Vec2& hi, F&& f) const {
    auto cx = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - m_lo.x()) / m_cell)), 0, m_nx - 1); };
    auto cy = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - m_lo.y()) / m_cell)), 0, m_ny - 1); };
    const int x0 = cx(lo.x() - m_tol), x1 = cx(hi.x() + m_tol), y0 = cy(lo.y() - m_tol), y1 = cy(hi.y() + m_tol);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(static_cast<std::size_t>(y) * static_cast<std::size_t>(m_nx) + static_cast<std::size_t>(x));
  }

  const Cage& m_cage;
  const std::vector<Edge>& m_edges;
  double m_tol;
  double m_cell = 1.0;
  Vec2 m_lo = Vec2::Zero();
  int m_nx = 1, m_ny = 1;
  std::vector<std::vector<int>> m_cells;
};

enum class Region : std::uint8_t { Inside, Boundary, Outside };

Region regionOf(SampleKind kind, bool closed) {
  if (!closed) return Region::Inside;  // open structures: one region, only crossings matter
  switch (kind) {
    case SampleKind::Control:
    case SampleKind::Edge: return Region::Boundary;
    case SampleKind::Exterior: return Region::Outside;
    default: return Region::Inside;
  }
}

/// The diffusion operator: K without the pairs whose segment crosses the cage, and directed so
/// heat never goes from the outside back in: samples inside or on the cage take heat only through
/// segments inside (or along) the cage; exterior samples take it from exterior and on-cage samples.
/// Without this, heat could leave the shape at an on-cage sample, cross a notch outside and enter
/// again at the other wall. Restricted to inside/on-cage rows (or to exterior rows) the operator is
/// symmetric: crossing tests use the ordered pair (min, max).
SparseRowMatrix diffusionOperator(const SampleSet& S, const Cage& cage, const SparseMatrix& K) {
  const Points& X = S.X;
  const auto edges = cageEdges(cage);
  const Index n = X.rows();
  const Vec2 lo = X.colwise().minCoeff().transpose().cwiseMin(cage.C.colwise().minCoeff().transpose());
  const Vec2 hi = X.colwise().maxCoeff().transpose().cwiseMax(cage.C.colwise().maxCoeff().transpose());
  double reach = 0.0;  // longest kernel pair: a segment's bounding box then meets ≤ 2×2 cells
  for (Index c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it)
      reach = std::max(reach, (X.row(it.row()) - X.row(c)).cwiseAbs().maxCoeff());
  const double extent = std::max(1e-300, (hi - lo).norm());
  const EdgeGrid grid(cage, edges, lo, hi, std::max(reach, 1e-6 * extent), 1e-9 * extent);
  const bool closed = cage.closed;

  std::vector<std::vector<std::pair<Index, double>>> rows(static_cast<std::size_t>(n));
  parallelFor(n, [&](Index i) {
    auto& row = rows[static_cast<std::size_t>(i)];
    const Region ri = regionOf(S.kind[static_cast<std::size_t>(i)], closed);
    for (SparseMatrix::InnerIterator it(K, i); it; ++it) {  // K symmetric: column i = row i
      const Index j = it.row();
      if (j != i) {
        const Region rj = regionOf(S.kind[static_cast<std::size_t>(j)], closed);
        const Region lower = std::min(ri, rj), upper = std::max(ri, rj);
        if (lower == Region::Inside && upper == Region::Outside) continue;  // must cross the cage
        // The side the segment runs on; for two on-cage samples, its midpoint decides.
        Region side = lower == Region::Inside ? Region::Inside : (upper == Region::Outside ? Region::Outside : Region::Boundary);
        const Vec2 a = X.row(std::min(i, j)).transpose(), b = X.row(std::max(i, j)).transpose();
        if (side == Region::Boundary) {
          const Vec2 mid = 0.5 * (a + b);
          if (distanceToCage(cage, mid) > 1e-9 * (b - a).norm())
            side = insideCage(cage, mid) ? Region::Inside : Region::Outside;
        }
        if (ri != Region::Outside && side == Region::Outside) continue;
        if (ri == Region::Outside && side == Region::Inside) continue;
        if (grid.crosses(a, b)) continue;
      }
      row.emplace_back(j, it.value());
    }
  });
  std::vector<Eigen::Triplet<double>> trip;
  for (Index i = 0; i < n; ++i)
    for (const auto& [j, v] : rows[static_cast<std::size_t>(i)]) trip.emplace_back(i, j, v);
  SparseRowMatrix R(n, n);
  R.setFromTriplets(trip.begin(), trip.end());
  return R;
}

/// (4.10): w_ij = 1 / (1 + (|x_j − c_i| / p)²).
void inverseDistanceRow(const Points& C, const Vec2& x, double p, Eigen::Ref<Eigen::RowVectorXd> w) {
  for (Index i = 0; i < C.rows(); ++i) {
    const double r = (Vec2(C.row(i)) - x).norm() / p;
    w(i) = 1.0 / (1.0 + r * r);
  }
}

/// Unknown samples from which some known sample can be reached through the operator's rows.
std::vector<char> reachableFromKnown(const SparseRowMatrix& R, const std::vector<Index>& unknown,
                                     const std::vector<char>& isUnknown) {
  const Index n = R.rows();
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  std::vector<Index> stack;
  for (Index i : unknown)
    for (SparseRowMatrix::InnerIterator it(R, i); it; ++it)
      if (!isUnknown[static_cast<std::size_t>(it.col())]) {
        seen[static_cast<std::size_t>(i)] = 1;
        stack.push_back(i);
        break;
      }
  // Within one stage the operator is symmetric, so following rows outwards finds the component.
  while (!stack.empty()) {
    const Index i = stack.back();
    stack.pop_back();
    for (SparseRowMatrix::InnerIterator it(R, i); it; ++it) {
      const auto j = static_cast<std::size_t>(it.col());
      if (isUnknown[j] && !seen[j]) {
        seen[j] = 1;
        stack.push_back(it.col());
      }
    }
  }
  return seen;
}

/// Steady state for the rows `unknown` (all others known): ((1+μ) D_UU − R_UU) W_U = R_UK W_K.
/// μ = 0 is the converged diffusion of (4.13); μ > 0 absorbs a fraction of the heat at every step
/// (screened diffusion), so heat from an edge decays exponentially with the distance travelled
/// inside the shape. The rows are then normalized to sum 1.
bool solveSteadyState(const SparseRowMatrix& R, const Eigen::VectorXd& D, const std::vector<Index>& unknown, double mu,
                      Weights& W, std::vector<Index>* vanished = nullptr) {
  const Index nu = static_cast<Index>(unknown.size());
  if (nu == 0) return true;
  std::vector<Index> slot(static_cast<std::size_t>(R.rows()), -1);
  for (Index f = 0; f < nu; ++f) slot[static_cast<std::size_t>(unknown[static_cast<std::size_t>(f)])] = f;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nu, W.cols());
  for (Index f = 0; f < nu; ++f) {
    const Index i = unknown[static_cast<std::size_t>(f)];
    trip.emplace_back(f, f, (1.0 + mu) * D(i));
    for (SparseRowMatrix::InnerIterator e(R, i); e; ++e) {
      const Index s = slot[static_cast<std::size_t>(e.col())];
      if (s >= 0)
        trip.emplace_back(f, s, -e.value());
      else
        rhs.row(f) += e.value() * W.row(e.col());
    }
  }
  SparseMatrix A(nu, nu);
  A.setFromTriplets(trip.begin(), trip.end());
  detail::SupernodalCholesky solver;
  solver.compute(A);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::MatrixXd WU = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !WU.allFinite()) return false;
  for (Index f = 0; f < nu; ++f) {
    const double sum = WU.row(f).sum();
    const Index i = unknown[static_cast<std::size_t>(f)];
    if (!(sum > 1e-200)) {  // screened away entirely: the caller solves this row unscreened
      if (!vanished) return false;
      vanished->push_back(i);
      continue;
    }
    W.row(i) = WU.row(f) / sum;
  }
  return true;
}

/// Moves a screened target row w0 (positive, sum 1) to reproduce x while staying close to it in
/// the metric Σ (w_i − w0_i)² / w0_i: min that s.t. Σ w_i c_i = x, Σ w_i = 1, w ≥ 0. Corrections
/// are proportional to the targets, so controls with negligible targets stay negligible (the
/// row stays local) and they are recruited only as far as reproduction needs them. Solved in the
/// 3-variable dual (w(λ) = max(0, w0 + w0 ∘ Aᵀλ), damped Newton). Returns false when x is not
/// reproducible with w ≥ 0 (outside the controls' hull) or Newton stalls; w0 is then left as is.
bool projectTargetsLocally(const Points& C, const Vec2& x, Eigen::Ref<Eigen::RowVectorXd> w0) {
  const Index m = C.rows();
  // Centred, scaled coordinates keep the 3×3 systems well conditioned.
  const Vec2 c0 = C.colwise().mean().transpose();
  const double scale = std::max(1e-300, (C.rowwise() - c0.transpose()).cwiseAbs().maxCoeff());
  Eigen::Matrix<double, 3, Eigen::Dynamic> A(3, m);
  for (Index i = 0; i < m; ++i) A.col(i) << (C(i, 0) - c0.x()) / scale, (C(i, 1) - c0.y()) / scale, 1.0;
  const Eigen::Vector3d b((x.x() - c0.x()) / scale, (x.y() - c0.y()) / scale, 1.0);
  // Metric weights: the targets, floored at 1e-8 of the largest so the dual stays well posed
  // where reproduction has to recruit controls whose screened targets underflowed.
  const Eigen::VectorXd d = w0.transpose().cwiseMax(1e-8 * w0.maxCoeff());
  auto weights = [&](const Eigen::Vector3d& lambda) {
    return Eigen::VectorXd((d.array() * (1.0 + (A.transpose() * lambda).array())).cwiseMax(0.0));
  };
  auto dual = [&](const Eigen::Vector3d& lambda, const Eigen::VectorXd& w) {  // convex, C¹
    return 0.5 * (w.array().square() / d.array()).sum() - b.dot(lambda) - 0.5 * d.sum();
  };
  Eigen::Vector3d lambda = Eigen::Vector3d::Zero();
  Eigen::VectorXd w = weights(lambda);
  for (int it = 0; it < 200; ++it) {
    const Eigen::Vector3d g = A * w - b;
    if (g.cwiseAbs().maxCoeff() <= 1e-11) {  // normalized units: ~1e-11 of the cage size
      w0 = w.transpose();
      return true;
    }
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    for (Index i = 0; i < m; ++i)
      if (w(i) > 0.0) H.noalias() += d(i) * A.col(i) * A.col(i).transpose();
    H.diagonal().array() += 1e-14 * (H.trace() + 1e-300);
    const Eigen::Vector3d step = -H.ldlt().solve(g);
    if (!step.allFinite()) return false;
    const double f0 = dual(lambda, w);
    double t = 1.0;
    Eigen::VectorXd wt;
    for (int k = 0; k < 60; ++k, t *= 0.5) {  // Armijo backtracking on the dual objective
      wt = weights(lambda + t * step);
      if (dual(lambda + t * step, wt) <= f0 + 1e-4 * t * g.dot(step)) break;
    }
    lambda += t * step;
    w = wt;
    if (!lambda.allFinite() || lambda.norm() > 1e12) return false;  // infeasible: λ diverges
  }
  return false;
}

}  // namespace

double automaticLocality(const Points& C) {
  return C.rows() == 0 ? 0.0 : kAutoLocalityFraction * (C.colwise().maxCoeff() - C.colwise().minCoeff()).norm();
}

Weights initialWeights(const SampleSet& S, const Cage& cage, const SparseMatrix& K, const InitOptions& options,
                       InitReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  const Index m = cage.size();
  if (m == 0) throw std::invalid_argument("initial weights: the cage has no control points");
  S.validate(m);
  const Index n = S.size();
  if (K.rows() != n || K.cols() != n)
    throw std::invalid_argument("initial weights: K is " + std::to_string(K.rows()) + "×" + std::to_string(K.cols()) +
                                " but there are " + std::to_string(n) + " samples");
  if (options.iterations < 0) throw std::invalid_argument("initial weights: iterations must be ≥ 0");
  const Points& X = S.X;
  const Points& C = cage.C;
  double p = options.inverseDistanceP;
  if (!(p > 0.0)) {
    const Vec2 lo = C.colwise().minCoeff(), hi = C.colwise().maxCoeff();
    p = std::max(0.1 * (hi - lo).norm(), 1e-12);
  }

  Weights W = Weights::Zero(n, m);
  InitReport rep;
  // Fixed rows: controls e_i (3.18, 4.11); in HeatLinear also edge samples, linear (4.7).
  std::vector<char> known(static_cast<std::size_t>(n), 0);
  for (Index i = 0; i < m; ++i) {
    W(i, i) = 1.0;
    known[static_cast<std::size_t>(i)] = 1;
  }
  if (options.method == InitMethod::HeatLinear) {
    for (Index j = m; j < n; ++j) {
      if (S.kind[static_cast<std::size_t>(j)] != SampleKind::Edge) continue;
      const int k = S.edge(j, 0), l = S.edge(j, 1);
      const Vec2 ck = C.row(k), cl = C.row(l), x = X.row(j);
      const double wk = std::clamp((x - cl).dot(ck - cl) / (ck - cl).squaredNorm(), 0.0, 1.0);
      W(j, k) = wk;
      W(j, l) = 1.0 - wk;
      known[static_cast<std::size_t>(j)] = 1;
    }
  }

  if (options.method == InitMethod::InverseDistance) {
    parallelFor(n - m, [&](Index r) { inverseDistanceRow(C, X.row(m + r).transpose(), p, W.row(m + r)); });
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (report) *report = rep;
    return W;
  }

  // Diffusion operator P = D⁻¹R, R = K restricted to the shape (rows normalized to sum 1).
  const SparseRowMatrix R = diffusionOperator(S, cage, K);
  const Eigen::VectorXd D = R * Eigen::VectorXd::Ones(n);
  // Screening μ for the locality length ℓ. A step of the walk P moves heat by s² = E|x_j − x_i|²;
  // its generator is (s²/4)Δ, so absorbing μ per step gives (s²/4)Δw = μw: decay exp(−d/ℓ) with
  // ℓ = s / (2√μ), i.e. μ = s² / (4ℓ²).
  double mu = 0.0;
  const double locality = options.locality >= 0.0 ? options.locality : automaticLocality(C);
  if (locality > 0.0 && options.method == InitMethod::HeatLinear) {
    double s2 = 0.0;
    for (Index i = 0; i < n; ++i)
      for (SparseRowMatrix::InnerIterator e(R, i); e; ++e) s2 += e.value() / D(i) * (X.row(e.col()) - X.row(i)).squaredNorm();
    s2 /= static_cast<double>(n);
    mu = s2 / (4.0 * locality * locality);
  }
  auto fallback = [&](Index i) {  // normalized (4.10) for samples heat cannot reach
    inverseDistanceRow(C, X.row(i).transpose(), p, W.row(i));
    W.row(i) /= W.row(i).sum();
    known[static_cast<std::size_t>(i)] = 1;
    ++rep.fallbackSamples;
  };

  // Two stages: inside/on-cage samples first, then exterior ones (which depend on the former,
  // never the reverse). Each stage's unknowns with no path to a known sample fall back.
  const bool closed = cage.closed;
  std::vector<Index> stages[2];
  for (Index i = 0; i < n; ++i)
    if (!known[static_cast<std::size_t>(i)])
      stages[regionOf(S.kind[static_cast<std::size_t>(i)], closed) == Region::Outside ? 1 : 0].push_back(i);
  std::vector<Index> active;  // rows updated by the iteration
  for (auto& stage : stages) {
    std::vector<char> isUnknown(static_cast<std::size_t>(n), 0);
    for (Index i : stage) isUnknown[static_cast<std::size_t>(i)] = 1;
    const std::vector<char> reach = reachableFromKnown(R, stage, isUnknown);
    std::vector<Index> solvable;
    for (Index i : stage) {
      if (reach[static_cast<std::size_t>(i)])
        solvable.push_back(i);
      else
        fallback(i);
    }
    if (options.iterations == 0) {
      // Rows the screening drove to nothing (heat underflowed on the way) take the unscreened
      // steady state; every other row keeps its screened one.
      std::vector<Index> vanished;
      const bool solved = solveSteadyState(R, D, solvable, mu, W, &vanished);
      if (!solved || !vanished.empty()) {
        Weights unscreened = W;
        const std::vector<Index>& retry = solved ? vanished : solvable;
        if (solveSteadyState(R, D, solvable, 0.0, unscreened)) {  // diagonally dominant: does not fail
          for (Index i : retry) W.row(i) = unscreened.row(i);
        } else {
          for (Index i : retry) fallback(i);
        }
        if (mu > 0.0) rep.unscreenedSamples += static_cast<Index>(retry.size());
      }
    } else {
      active.insert(active.end(), solvable.begin(), solvable.end());
    }
  }

  if (mu > 0.0 && options.iterations == 0) {
    // Screened rows are local but do not reproduce their positions; left so, the per-sample QP's
    // correction (linear in the control positions) would hand far controls small weights. Give
    // each row positional accuracy here, with corrections proportional to its own targets.
    parallelFor(n, [&](Index i) {
      if (known[static_cast<std::size_t>(i)]) return;  // controls, edges and fallback rows
      const SampleKind k = S.kind[static_cast<std::size_t>(i)];
      if (k == SampleKind::Interior || k == SampleKind::Exterior || k == SampleKind::Line)
        projectTargetsLocally(C, X.row(i).transpose(), W.row(i));
    });
  }

  if (options.iterations > 0) {
    // (4.12)/(4.13): W_F ← (P W)_F, known rows unchanged; each row written by one task.
    std::sort(active.begin(), active.end());
    Weights next = W;
    for (int it = 0; it < options.iterations; ++it) {
      parallelFor(static_cast<Index>(active.size()), [&](Index f) {
        const Index i = active[static_cast<std::size_t>(f)];
        auto row = next.row(i);
        row.setZero();
        for (SparseRowMatrix::InnerIterator e(R, i); e; ++e) row.noalias() += e.value() * W.row(e.col());
        row /= D(i);
      }, /*grain=*/512);  // few, large tasks: one parallel region per sweep
      W.swap(next);  // rows not in `active` are equal in both buffers
    }
    rep.iterations = options.iterations;
  } else {
    rep.steadyState = true;
  }
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (report) *report = rep;
  return W;
}

}  // namespace kc
