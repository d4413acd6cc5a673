#pragma once
// Private to kc::core: large dense buffers backed by transparent huge pages where the system
// allows it. A first touch of fresh memory costs a page fault per 4 KiB page; on a virtual machine
// each fault can take 10–40 µs, so a release of a rigid region (~25 MB of fresh dense matrices)
// spent more in faults than in arithmetic (docs/rigidity.md, "Speed"). With huge pages one fault
// maps 2 MiB. Linux only (madvise MADV_HUGEPAGE, honoured when the kernel's THP mode is `always` or
// `madvise`); elsewhere, or when refused, the memory is ordinary.

#include <cstddef>
#include <memory>

namespace kc::detail {

/// Asks for huge pages over the whole 2 MiB-aligned pages inside [p, p + bytes) before they are
/// first touched (memory already touched keeps its pages). Does nothing below 2 MiB.
void preferHugePages(void* p, std::size_t bytes);

/// The same for a dense Eigen matrix's storage (call after resizing, before writing it).
template <class Matrix>
void preferHugePages(Matrix& m) {
  preferHugePages(static_cast<void*>(m.data()), sizeof(typename Matrix::Scalar) * std::size_t(m.size()));
}

struct FreeDeleter {
  void operator()(double* p) const;
};
using HugeArray = std::unique_ptr<double[], FreeDeleter>;

/// An uninitialized array of `count` doubles, aligned to 2 MiB when it is that large (so that all
/// of it can be huge pages) and with preferHugePages applied.
HugeArray allocateHuge(std::size_t count);

}  // namespace kc::detail
