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
std::vector<detail::SparseList> neighbourLists(const Points& X, const Points& P, const GaussianKernel& kernel,
                                               const Eigen::VectorXd& sx) {
  const SpatialGrid grid(X, kernel.cutoff());
  std::vector<detail::SparseList> rows(static_cast<std::size_t>(P.rows()));
  if (kernel.variable()) {  // Gibbs kernel: the widths at the samples and at each query point
    const bool same = &X == &P;
    parallelFor(P.rows(), [&](Index p) {
      auto& row = rows[static_cast<std::size_t>(p)];
      const Vec2 q = P.row(p).transpose();
      const double sp = same ? sx(p) : kernel.widthAt(q);
      grid.forEachWithin(q, kernel.reach(sp), [&](Index j, double d2) {
        const double v = kernel(d2, sp, sx(j));
        if (v != 0.0) row.emplace_back(j, v);
      });
      std::sort(row.begin(), row.end(), [](const Entry& a, const Entry& b) { return a.first < b.first; });
    });
    return rows;
  }
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
  return detail::compressLists<SparseMatrix>(X.rows(), X.rows(), neighbourLists(X, X, kernel, kernel.widthsAt(X)));
}

void kernelGradientRows(const Points& X, const Points& P, const GaussianKernel& kernel, SparseRowMatrix& Gx, SparseRowMatrix& Gy,
                        const Eigen::VectorXd* widths) {
  const Eigen::VectorXd computed = widths || !kernel.variable() ? Eigen::VectorXd() : kernel.widthsAt(X);
  const Eigen::VectorXd& sx = widths ? *widths : computed;
  Gx = kernelRows(X, P, kernel, &sx);
  Gy = Gx;
  const bool variable = kernel.variable();
  const double inv2 = 1.0 / (kernel.sigma * kernel.sigma);
  parallelFor(P.rows(), [&](Index p) {
    const Vec2 q = P.row(p).transpose();
    Vec2 gp = Vec2::Zero();
    const double sp = variable ? kernel.widthAt(q, gp) : kernel.sigma;
    SparseRowMatrix::InnerIterator y(Gy, p);
    for (SparseRowMatrix::InnerIterator x(Gx, p); x; ++x, ++y) {
      const Index j = x.col();
      if (!variable) {  // ∇k(p, x_j) = −k(p, x_j)(p − x_j)/σ² (3.42)
        x.valueRef() *= -inv2 * (q.x() - X(j, 0));
        y.valueRef() *= -inv2 * (q.y() - X(j, 1));
        continue;
      }
      const Vec2 f = kernel.gradientFactor(q - Vec2(X.row(j)), sp, gp, sx(j));
      x.valueRef() *= f.x();
      y.valueRef() *= f.y();
    }
  });
}

SparseRowMatrix kernelRows(const Points& X, const Points& P, const GaussianKernel& kernel, const Eigen::VectorXd* widths) {
  checkKernel(kernel);
  if (!X.allFinite()) throw std::invalid_argument("kernel rows: sample positions must be finite");
  if (!P.allFinite()) throw std::invalid_argument("kernel rows: query points must be finite");
  if (widths && kernel.variable() && widths->size() != X.rows())
    throw std::invalid_argument("kernel rows: one width per sample is needed");
  if (widths || !kernel.variable())
    return detail::compressLists<SparseRowMatrix>(P.rows(), X.rows(),
                                                  neighbourLists(X, P, kernel, widths ? *widths : Eigen::VectorXd()));
  return detail::compressLists<SparseRowMatrix>(P.rows(), X.rows(), neighbourLists(X, P, kernel, kernel.widthsAt(X)));
}

}  // namespace kc
