#pragma once
/// The one place where kcwarp's numerics go parallel. Every loop writes only its own rows, so
/// results are bit-identical for any thread count.

#include <functional>

#include "kc/core/types.h"

namespace kc {

/// Threads used by parallelFor (default: OpenMP's default, i.e. all cores).
int threadCount();
/// Sets the thread count for later parallelFor calls; n ≤ 0 restores the default.
void setThreadCount(int n);

/// Calls body(begin, end) on disjoint consecutive ranges covering [0, n), in parallel.
/// grain = the largest range handed to one call. Exceptions thrown by body are caught inside
/// the parallel region; the first one (lowest range) is rethrown after the loop.
void parallelForRange(Index n, Index grain, const std::function<void(Index, Index)>& body);

/// Calls body(i) for i in [0, n) in parallel (ranges of `grain` indices per task).
template <class F>
void parallelFor(Index n, F&& body, Index grain = 64) {
  parallelForRange(n, grain, [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) body(i);
  });
}

/// Scoped thread-count override (tests, benchmarks).
class ScopedThreadCount {
 public:
  explicit ScopedThreadCount(int n) : m_previous(threadCount()) { setThreadCount(n); }
  ~ScopedThreadCount() { setThreadCount(m_previous); }
  ScopedThreadCount(const ScopedThreadCount&) = delete;
  ScopedThreadCount& operator=(const ScopedThreadCount&) = delete;

 private:
  int m_previous;
};

}  // namespace kc
