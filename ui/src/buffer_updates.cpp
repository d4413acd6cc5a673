#include "kc/ui/buffer_updates.h"

#include <cstring>

namespace kc::ui {

std::vector<ElementRun> changedRuns(const void* before, const void* after, std::size_t n, std::size_t elementBytes,
                                    std::size_t gap) {
  const auto* a = static_cast<const unsigned char*>(before);
  const auto* b = static_cast<const unsigned char*>(after);
  std::vector<ElementRun> runs;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::memcmp(a + i * elementBytes, b + i * elementBytes, elementBytes) == 0) continue;
    if (!runs.empty() && i - runs.back().second < gap) runs.back().second = i + 1;
    else runs.emplace_back(i, i + 1);
  }
  return runs;
}

std::size_t runElements(const std::vector<ElementRun>& runs) {
  std::size_t n = 0;
  for (const ElementRun& r : runs) n += r.second - r.first;
  return n;
}

}  // namespace kc::ui
