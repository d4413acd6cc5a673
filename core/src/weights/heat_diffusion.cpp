#include "kc/core/weights/heat_diffusion.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kc/core/parallel.h"
#include "../sparse_cholesky.h"
#include "diffusion_operator.h"
#include "local_projection.h"

namespace kc {
namespace {

using detail::diffusionOperator;
using detail::projectTargetsLocally;
using detail::reachableFromKnown;
using detail::Region;
using detail::regionOf;

/// (4.10): w_ij = 1 / (1 + (|x_j − c_i| / p)²).
void inverseDistanceRow(const Points& C, const Vec2& x, double p, Eigen::Ref<Eigen::RowVectorXd> w) {
  for (Index i = 0; i < C.rows(); ++i) {
    const double r = (Vec2(C.row(i)) - x).norm() / p;
    w(i) = 1.0 / (1.0 + r * r);
  }
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
  // A is symmetric (within a stage the operator is), so only its lower triangle is built: column
  // f holds row f's entries in columns s ≥ f (unknown is increasing, so they come in order).
  std::vector<int> start(static_cast<std::size_t>(nu) + 1, 0);
  for (Index f = 0; f < nu; ++f) {
    int count = 1;  // the diagonal
    for (SparseRowMatrix::InnerIterator e(R, unknown[static_cast<std::size_t>(f)]); e; ++e)
      count += slot[static_cast<std::size_t>(e.col())] > f;
    start[static_cast<std::size_t>(f) + 1] = start[static_cast<std::size_t>(f)] + count;
  }
  SparseMatrix A(nu, nu);
  A.resizeNonZeros(start.back());
  std::copy(start.begin(), start.end(), A.outerIndexPtr());
  int* row = A.innerIndexPtr();
  double* value = A.valuePtr();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nu, W.cols());
  for (Index f = 0; f < nu; ++f) {
    const Index i = unknown[static_cast<std::size_t>(f)];
    int k = start[static_cast<std::size_t>(f)];
    row[k] = static_cast<int>(f);
    value[k++] = (1.0 + mu) * D(i);
    for (SparseRowMatrix::InnerIterator e(R, i); e; ++e) {
      const Index s = slot[static_cast<std::size_t>(e.col())];
      if (s < 0) {
        rhs.row(f) += e.value() * W.row(e.col());
      } else if (s == f) {
        value[start[static_cast<std::size_t>(f)]] += -e.value();
      } else if (s > f) {
        row[k] = static_cast<int>(s);
        value[k++] = -e.value();
      }
    }
  }
  detail::PermutedCholesky solver;
  solver.compute(std::move(A));
  if (!solver.ok()) return false;
  const Eigen::MatrixXd WU = solver.solve(rhs);
  if (!WU.allFinite()) return false;
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

/// Rows fixed before the diffusion, marked in `known`: controls e_i (3.18, 4.11) and, in
/// HeatLinear, edge samples linear along their edge (4.7).
void fixKnownRows(const SampleSet& S, const Points& C, InitMethod method, Weights& W, std::vector<char>& known) {
  const Index m = C.rows(), n = S.size();
  for (Index i = 0; i < m; ++i) {
    W(i, i) = 1.0;
    known[static_cast<std::size_t>(i)] = 1;
  }
  if (method != InitMethod::HeatLinear) return;
  for (Index j = m; j < n; ++j) {
    if (S.kind[static_cast<std::size_t>(j)] != SampleKind::Edge) continue;
    const int k = S.edge(j, 0), l = S.edge(j, 1);
    const Vec2 ck = C.row(k), cl = C.row(l), x = S.X.row(j);
    const double wk = std::clamp((x - cl).dot(ck - cl) / (ck - cl).squaredNorm(), 0.0, 1.0);
    W(j, k) = wk;
    W(j, l) = 1.0 - wk;
    known[static_cast<std::size_t>(j)] = 1;
  }
}

/// Screening μ for the locality length ℓ > 0. A step of the walk P = D⁻¹R moves heat by
/// s² = E|x_j − x_i|²; its generator is (s²/4)Δ, so absorbing μ per step gives (s²/4)Δw = μw:
/// decay exp(−d/ℓ) with ℓ = s / (2√μ), i.e. μ = s² / (4ℓ²).
double screeningFor(const SparseRowMatrix& R, const Eigen::VectorXd& D, const Points& X, double locality) {
  const Index n = X.rows();
  double s2 = 0.0;
  for (Index i = 0; i < n; ++i)
    for (SparseRowMatrix::InnerIterator e(R, i); e; ++e) s2 += e.value() / D(i) * (X.row(e.col()) - X.row(i)).squaredNorm();
  s2 /= static_cast<double>(n);
  return s2 / (4.0 * locality * locality);
}

/// The diffusion of the unknown rows of W, one stage of samples at a time.
struct Diffusion {
  const SparseRowMatrix& R;  // the operator P = D⁻¹R
  const Eigen::VectorXd& D;
  const Points& C;
  const Points& X;
  double p;  // inverse-distance power of the fallback
  Weights& W;
  std::vector<char>& known;
  InitReport& rep;

  /// Row i normalized inverse distance (4.10), for samples heat cannot reach.
  void fallback(Index i) {
    inverseDistanceRow(C, X.row(i).transpose(), p, W.row(i));
    W.row(i) /= W.row(i).sum();
    known[static_cast<std::size_t>(i)] = 1;
    ++rep.fallbackSamples;
  }

  /// One stage's rows: those with no path to a known sample fall back; with iterations = 0 the
  /// others take the steady state screened by μ (rows the screening drove to nothing — heat
  /// underflowed on the way — the unscreened one), else they are appended to `active` for the
  /// iteration.
  void stage(const std::vector<Index>& rows, double mu, int iterations, std::vector<Index>& active) {
    std::vector<char> isUnknown(static_cast<std::size_t>(X.rows()), 0);
    for (Index i : rows) isUnknown[static_cast<std::size_t>(i)] = 1;
    const std::vector<char> reach = reachableFromKnown(R, rows, isUnknown);
    std::vector<Index> solvable;
    for (Index i : rows) {
      if (reach[static_cast<std::size_t>(i)])
        solvable.push_back(i);
      else
        fallback(i);
    }
    if (iterations > 0) {
      active.insert(active.end(), solvable.begin(), solvable.end());
      return;
    }
    std::vector<Index> vanished;
    const bool solved = solveSteadyState(R, D, solvable, mu, W, &vanished);
    if (solved && vanished.empty()) return;
    Weights unscreened = W;
    const std::vector<Index>& retry = solved ? vanished : solvable;
    if (solveSteadyState(R, D, solvable, 0.0, unscreened)) {  // diagonally dominant: does not fail
      for (Index i : retry) W.row(i) = unscreened.row(i);
    } else {
      for (Index i : retry) fallback(i);
    }
    if (mu > 0.0) rep.unscreenedSamples += static_cast<Index>(retry.size());
  }
};

/// (4.12)/(4.13): `iterations` sweeps W_F ← (P W)_F over the rows F = `active`, the others
/// unchanged; each row written by one task.
void iterateDiffusion(const SparseRowMatrix& R, const Eigen::VectorXd& D, std::vector<Index> active, int iterations, Weights& W) {
  std::sort(active.begin(), active.end());
  Weights next = W;
  for (int it = 0; it < iterations; ++it) {
    parallelFor(static_cast<Index>(active.size()), [&](Index f) {
      const Index i = active[static_cast<std::size_t>(f)];
      auto row = next.row(i);
      row.setZero();
      for (SparseRowMatrix::InnerIterator e(R, i); e; ++e) row.noalias() += e.value() * W.row(e.col());
      row /= D(i);
    }, /*grain=*/512);  // few, large tasks: one parallel region per sweep
    W.swap(next);  // rows not in `active` are equal in both buffers
  }
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
  if (options.locality && !(std::isfinite(*options.locality) && *options.locality > 0.0))
    throw std::invalid_argument("initial weights: the locality length must be a finite number > 0 (none = unscreened)");
  if (options.method == InitMethod::Lbc)
    throw std::invalid_argument("initial weights: LBC targets are solved on a mesh of the cage (app's kc backend), not here");
  const Points& X = S.X;
  const Points& C = cage.C;
  double p = options.inverseDistanceP;
  if (!(p > 0.0)) {
    const Vec2 lo = C.colwise().minCoeff(), hi = C.colwise().maxCoeff();
    p = std::max(0.1 * (hi - lo).norm(), 1e-12);
  }

  Weights W = Weights::Zero(n, m);
  InitReport rep;
  std::vector<char> known(static_cast<std::size_t>(n), 0);
  fixKnownRows(S, C, options.method, W, known);

  if (options.method == InitMethod::InverseDistance) {
    parallelFor(n - m, [&](Index r) { inverseDistanceRow(C, X.row(m + r).transpose(), p, W.row(m + r)); });
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (report) *report = rep;
    return W;
  }

  // Diffusion operator P = D⁻¹R, R = K restricted to the shape (rows normalized to sum 1).
  const SparseRowMatrix R = diffusionOperator(S, cage, K);
  const Eigen::VectorXd D = R * Eigen::VectorXd::Ones(n);
  const double mu = options.locality && options.method == InitMethod::HeatLinear ? screeningFor(R, D, X, *options.locality) : 0.0;

  // Two stages: inside/on-cage samples first, then exterior ones (which depend on the former,
  // never the reverse). Each stage's unknowns with no path to a known sample fall back.
  const bool closed = hasInterior(cage);
  std::vector<Index> stages[2];
  for (Index i = 0; i < n; ++i)
    if (!known[static_cast<std::size_t>(i)])
      stages[regionOf(S.kind[static_cast<std::size_t>(i)], closed) == Region::Outside ? 1 : 0].push_back(i);
  Diffusion diffusion{R, D, C, X, p, W, known, rep};
  std::vector<Index> active;  // rows updated by the iteration
  for (const auto& stage : stages) diffusion.stage(stage, mu, options.iterations, active);

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
    iterateDiffusion(R, D, std::move(active), options.iterations, W);
    rep.iterations = options.iterations;
  } else {
    rep.steadyState = true;
  }
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (report) *report = rep;
  return W;
}

void floorTargets(const SampleSet& S, Weights& W0, double floor) {
  if (!(floor >= 0.0) || !std::isfinite(floor))
    throw std::invalid_argument("floorTargets: the floor must be a finite number >= 0");
  if (W0.rows() != S.size()) throw std::invalid_argument("floorTargets: W0 must have one row per sample");
  if (floor == 0.0) return;
  for (Index i = 0; i < W0.rows(); ++i) {
    const SampleKind kind = S.kind[std::size_t(i)];
    if (kind != SampleKind::Interior && kind != SampleKind::Exterior) continue;
    auto row = W0.row(i).array();
    const double sum = (row - floor).cwiseMax(0.0).sum();
    if (sum > 0.0) row = (row - floor).cwiseMax(0.0) / sum;  // element-wise: no temporary row
  }
}

}  // namespace kc
