#include "kc/core/parallel.h"

#include <omp.h>

#include "blas_threads.h"

#include <algorithm>
#include <exception>
#include <vector>

// OpenBLAS's thread count, when the BLAS loaded is OpenBLAS (weak: null otherwise).
extern "C" void openblas_set_num_threads(int) __attribute__((weak));
extern "C" int openblas_get_num_threads() __attribute__((weak));

namespace kc {
namespace {
int g_threads = 0;  // 0 = OpenMP default
}

void detail::serialBlas() {
  if (openblas_set_num_threads && openblas_get_num_threads && openblas_get_num_threads() != 1) openblas_set_num_threads(1);
}

int threadCount() { return g_threads > 0 ? g_threads : omp_get_max_threads(); }

void setThreadCount(int n) { g_threads = std::max(0, n); }

void parallelForRange(Index n, Index grain, const std::function<void(Index, Index)>& body) {
  if (n <= 0) return;
  grain = std::max<Index>(1, grain);
  const Index chunks = (n + grain - 1) / grain;
  const int threads = static_cast<int>(std::min<Index>(threadCount(), chunks));
  if (threads <= 1) {
    body(0, n);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(chunks));
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (Index c = 0; c < chunks; ++c) {
    try {
      body(c * grain, std::min(n, (c + 1) * grain));
    } catch (...) {
      errors[static_cast<std::size_t>(c)] = std::current_exception();
    }
  }
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace kc
