#include "kc/core/kernel/kernel_matrix.h"

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "kc/core/parallel.h"
#include "kc/core/spatial_grid.h"
#include "../sparse_lists.h"

namespace kc {
namespace {

void checkKernel(const GaussianKernel& kernel) {
  if (!(kernel.sigma > 0.0) || !std::isfinite(kernel.sigma))
    throw std::invalid_argument("kernel: sigma must be positive and finite");
  if (!(kernel.cutoffFactor > 0.0) || !std::isfinite(kernel.cutoffFactor))
    throw std::invalid_argument("kernel: cut-off factor must be positive and finite");
  if (!(kernel.scale > 0.0) || !std::isfinite(kernel.scale))
    throw std::invalid_argument("kernel: scale must be positive and finite");
}

using Entry = detail::SparseList::value_type;  // (sample index, kernel value)

/// For every query row, the kernel values of the samples within the cut-off, sorted by index.
/// Each parallel task writes only its own rows.
std::vector<detail::SparseList> neighbourLists(const Points& X, const Points& P, const GaussianKernel& kernel) {
  const SpatialGrid grid(X, kernel.cutoff());
  std::vector<detail::SparseList> rows(static_cast<std::size_t>(P.rows()));
  parallelFor(P.rows(), [&](Index p) {
    auto& row = rows[static_cast<std::size_t>(p)];
    grid.forEachWithin(P.row(p).transpose(), kernel.cutoff(),
                       [&](Index j, double d2) { row.emplace_back(j, kernel(d2)); });
    std::sort(row.begin(), row.end(), [](const Entry& a, const Entry& b) { return a.first < b.first; });
  });
  return rows;
}

}  // namespace

SparseMatrix assembleKernelMatrix(const Points& X, const GaussianKernel& kernel) {
  checkKernel(kernel);
  if (!X.allFinite()) throw std::invalid_argument("kernel matrix: sample positions must be finite");
  // K is symmetric, so column i holds the same entries as row i: build the columns directly.
  return detail::compressLists<SparseMatrix>(X.rows(), X.rows(), neighbourLists(X, X, kernel));
}

SparseRowMatrix kernelRows(const Points& X, const Points& P, const GaussianKernel& kernel) {
  checkKernel(kernel);
  if (!X.allFinite()) throw std::invalid_argument("kernel rows: sample positions must be finite");
  if (!P.allFinite()) throw std::invalid_argument("kernel rows: query points must be finite");
  return detail::compressLists<SparseRowMatrix>(P.rows(), X.rows(), neighbourLists(X, P, kernel));
}

}  // namespace kc
