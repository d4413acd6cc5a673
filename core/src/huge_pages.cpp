#include "huge_pages.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace kc::detail {
namespace {
constexpr std::size_t kHuge = std::size_t(2) << 20;
}

void preferHugePages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (bytes < kHuge) return;
  const auto begin = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) / kHuge * kHuge;
  const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes) / kHuge * kHuge;
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a refusal leaves ordinary pages
#else
  (void)p, (void)bytes;
#endif
}

void FreeDeleter::operator()(double* p) const { std::free(p); }

HugeArray allocateHuge(std::size_t count) {
  const std::size_t bytes = std::max<std::size_t>(count, 1) * sizeof(double);
  void* p = bytes >= kHuge ? std::aligned_alloc(kHuge, (bytes + kHuge - 1) / kHuge * kHuge) : std::malloc(bytes);
  if (!p) throw std::bad_alloc();
  preferHugePages(p, bytes);
  return HugeArray(static_cast<double*>(p));
}

}  // namespace kc::detail
