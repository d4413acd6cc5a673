#pragma once
/// Compressed sparse storage built straight from per-outer-index lists (core-internal).

#include <cstddef>
#include <utility>
#include <vector>

#include "kc/core/types.h"

namespace kc::detail {

/// The (inner index, value) pairs of one outer index (a column of a column-major matrix, a row of
/// a row-major one), in increasing inner order.
using SparseList = std::vector<std::pair<Index, double>>;

/// A rows × cols matrix of storage order Sparse (Eigen::SparseMatrix) whose outer index o holds
/// lists[o] ((inner index, value) pairs, increasing inner index; any integer index type). Each list
/// is freed once copied, so the peak is the lists plus the matrix, not twice the lists (no
/// triplets, no sort).
template <class Sparse, class Entry>
Sparse compressLists(Index rows, Index cols, std::vector<std::vector<Entry>>&& lists) {
  Sparse M(rows, cols);
  std::size_t nnz = 0;
  for (const auto& l : lists) nnz += l.size();
  M.resizeNonZeros(static_cast<Index>(nnz));
  auto* outer = M.outerIndexPtr();
  auto* inner = M.innerIndexPtr();
  double* value = M.valuePtr();
  std::size_t k = 0;
  outer[0] = 0;
  for (std::size_t o = 0; o < lists.size(); ++o) {
    for (const auto& [j, v] : lists[o]) {
      inner[k] = static_cast<typename Sparse::StorageIndex>(j);
      value[k++] = v;
    }
    outer[o + 1] = static_cast<typename Sparse::StorageIndex>(k);
    std::vector<Entry>().swap(lists[o]);
  }
  return M;
}

}  // namespace kc::detail
