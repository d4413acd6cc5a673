#pragma once
/// Which parts of a vertex buffer changed since its last upload, so that the renderer sends the
/// GPU only those (glBufferSubData per run) instead of the whole buffer.

#include <cstddef>
#include <utility>
#include <vector>

namespace kc::ui {

/// A run of elements [begin, end).
using ElementRun = std::pair<std::size_t, std::size_t>;

/// The runs of elements (each `elementBytes` bytes) where `before` and `after` (n elements each)
/// differ, in order; runs separated by fewer than `gap` equal elements are merged into one (fewer,
/// larger uploads). Empty when nothing changed.
std::vector<ElementRun> changedRuns(const void* before, const void* after, std::size_t n, std::size_t elementBytes,
                                    std::size_t gap);

/// Elements covered by `runs`.
std::size_t runElements(const std::vector<ElementRun>& runs);

}  // namespace kc::ui
