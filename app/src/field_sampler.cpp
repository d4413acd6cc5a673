#include "kc/app/field_sampler.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "kc/core/parallel.h"

namespace kc::app {

FieldSampler::FieldSampler(const CoordinateField& field, const Points& P) : m_P(P) {
  if (!field.interpolator.ok()) throw std::invalid_argument("FieldSampler: the coordinate field is not computed");
  m_K = kernelRows(field.interpolator.samples(), P, field.interpolator.kernel());
}

void FieldSampler::updateColumns(const KernelCoefficients& coef, std::span<const Index> columns, Weights& W) const {
  const Index m = coef.U.cols();
  if (coef.U.rows() != m_K.cols()) throw std::invalid_argument("FieldSampler: coefficients belong to other samples");
  if (W.rows() != m_P.rows() || W.cols() != m) throw std::invalid_argument("FieldSampler: W must be #P×m");
  const Index c = static_cast<Index>(columns.size());
  RowMatrix U(coef.U.rows(), c);
  Eigen::Matrix<double, 3, Eigen::Dynamic> B(3, c);
  for (Index k = 0; k < c; ++k) {
    const Index col = columns[static_cast<std::size_t>(k)];
    if (col < 0 || col >= m) throw std::invalid_argument("FieldSampler: column " + std::to_string(col) + " out of range");
    U.col(k) = coef.U.col(col);
    B.col(k) = coef.B.col(col);
  }
  // Each point writes only its own row: identical results for any thread count.
  parallelFor(m_P.rows(), [&](Index p) {
    Eigen::RowVectorXd row = B.row(0) + m_P(p, 0) * B.row(1) + m_P(p, 1) * B.row(2);
    for (SparseRowMatrix::InnerIterator it(m_K, p); it; ++it) row.noalias() += it.value() * U.row(it.col());
    for (Index k = 0; k < c; ++k) W(p, columns[static_cast<std::size_t>(k)]) = row(k);
  }, 256);
}

Weights FieldSampler::evaluate(const KernelCoefficients& coef) const {
  Weights W(m_P.rows(), coef.U.cols());
  std::vector<Index> all(static_cast<std::size_t>(coef.U.cols()));
  for (Index k = 0; k < coef.U.cols(); ++k) all[static_cast<std::size_t>(k)] = k;
  updateColumns(coef, all, W);
  return W;
}

}  // namespace kc::app
