#include "kc/core/weights/optimizer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>
#include <stdexcept>
#include <string>

#include "kc/core/parallel.h"

namespace kc {

void WeightOptimizer::precompute(const Points& C) {
  m_frame = ControlFrame(C);  // validates C
  m_C = C;
}

OptimizeReport WeightOptimizer::optimize(const SampleSet& S, const Weights& W0, Weights& W,
                                         const OptimizeOptions& options, std::span<const Index> subset) const {
  const auto t0 = std::chrono::steady_clock::now();
  const Index m = m_C.rows();
  if (m == 0) throw std::invalid_argument("optimize: no control points (call precompute first)");
  S.validate(m);
  const Index n = S.size();
  if (W0.rows() != n || W0.cols() != m)
    throw std::invalid_argument("optimize: initial weights are " + std::to_string(W0.rows()) + "×" +
                                std::to_string(W0.cols()) + ", expected " + std::to_string(n) + "×" + std::to_string(m));
  if (!W0.allFinite()) throw std::invalid_argument("optimize: initial weights contain NaN or infinity");
  for (Index j : subset)
    if (j < 0 || j >= n)
      throw std::invalid_argument("optimize: sample index " + std::to_string(j) + " out of range [0, " +
                                  std::to_string(n) + ")");
  if (subset.empty()) {
    if (W.rows() != n || W.cols() != m) W.resize(n, m);
  } else if (W.rows() != n || W.cols() != m) {
    throw std::invalid_argument("optimize: weights are " + std::to_string(W.rows()) + "×" + std::to_string(W.cols()) +
                                ", expected " + std::to_string(n) + "×" + std::to_string(m) + " for a subset update");
  }
  if (&W == &W0) throw std::invalid_argument("optimize: W and W0 must be different matrices");
  const double epsilon = options.allowance;
  if (!(epsilon >= 0.0 && std::isfinite(epsilon)))
    throw std::invalid_argument("optimize: the QP allowance must be finite and >= 0");
  const bool weighted = options.method == Method::QP && epsilon > 0.0;

  const Index count = subset.empty() ? n : static_cast<Index>(subset.size());
  std::atomic<Index> infeasible{0}, failed{0};
  std::atomic<int> maxIterations{0};
  const auto ms = static_cast<std::size_t>(m);

  parallelForRange(count, 256, [&](Index begin, Index end) {
    Index localInfeasible = 0, localFailed = 0;
    int localMax = 0;
    std::vector<double> allowance(weighted ? ms : 0);
    for (Index c = begin; c < end; ++c) {
      const Index j = subset.empty() ? c : subset[static_cast<std::size_t>(c)];
      const std::span<const double> w0(W0.row(j).data(), ms);
      const std::span<double> w(W.row(j).data(), ms);
      const SampleKind kind = S.kind[static_cast<std::size_t>(j)];
      const Vec2 x(S.X.row(j));
      if (kind == SampleKind::Control) {
        std::fill(w.begin(), w.end(), 0.0);
        w[static_cast<std::size_t>(j)] = 1.0;  // Lagrange property (3.18): sample j < m is control j
        continue;
      }
      if (kind == SampleKind::Edge) {
        edgeWeights(m_C, S.edge(j, 0), S.edge(j, 1), x, w);
        continue;
      }
      const Vec2 xh = m_frame.normalize(x);
      SampleReport r;
      switch (options.method) {
        case Method::QEC: sampleQec(m_frame, xh, w0, w); break;
        case Method::QP:
          if (weighted) {
            for (Index i = 0; i < m; ++i) allowance[static_cast<std::size_t>(i)] = allowanceOf(W0(j, i), epsilon);
            r = sampleQpWeighted(m_frame, xh, w0, allowance, w, options.qp);
          } else {
            r = sampleQp(m_frame, xh, w0, w, options.qp);
          }
          break;
        case Method::L1: r = sampleL1(m_frame, xh, w0, w, options.l1); break;
      }
      if (r.status == SolveStatus::Infeasible) ++localInfeasible;
      if (r.status == SolveStatus::NotConverged) ++localFailed;
      localMax = std::max(localMax, r.iterations);
    }
    infeasible += localInfeasible;
    failed += localFailed;
    int seen = maxIterations.load();
    while (localMax > seen && !maxIterations.compare_exchange_weak(seen, localMax)) {
    }
  });

  OptimizeReport report;
  report.solved = count;
  report.infeasible = infeasible.load();
  report.failed = failed.load();
  report.maxIterations = maxIterations.load();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace kc
