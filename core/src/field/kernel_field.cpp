#include "kc/core/field/kernel_field.h"

#include <stdexcept>
#include <string>
#include <utility>


namespace kc {

InterpolatorReport KernelField::compute(const Points& X, const GaussianKernel& kernel, InterpMode mode) {
  m_coef = {};
  m_lift.resize(0, 0);
  return m_interp.compute(X, kernel, mode);
}

InterpolatorReport KernelField::compute(const Points& X, const GaussianKernel& kernel, InterpMode mode, SparseMatrix&& K) {
  m_coef = {};
  m_lift.resize(0, 0);
  return m_interp.compute(X, kernel, mode, std::move(K));
}

void KernelField::restore(const Points& X, const GaussianKernel& kernel, InterpMode mode, const RowMatrix& Coef,
                          const RowMatrix& lift) {
  if (Coef.rows() != kPolynomialNodes + X.rows() || Coef.cols() == 0)
    throw std::invalid_argument("kernel field: coefficients have " + std::to_string(Coef.rows()) + " rows but " +
                                std::to_string(X.rows()) + " samples need " + std::to_string(kPolynomialNodes + X.rows()));
  if (!Coef.allFinite()) throw std::invalid_argument("kernel field: coefficients must be finite");
  m_interp.prepare(X, kernel, mode);
  m_coef.B = Coef.topRows(kPolynomialNodes);
  m_coef.U = Coef.bottomRows(X.rows());
  m_lift.resize(0, 0);
  if (lift.size() > 0) {
    if (lift.rows() != X.rows() || lift.cols() != Coef.cols())
      throw std::invalid_argument("kernel field: the lift has " + std::to_string(lift.rows()) + "×" +
                                  std::to_string(lift.cols()) + " entries but the coefficients need " + std::to_string(X.rows()) +
                                  "×" + std::to_string(Coef.cols()));
    if (!lift.allFinite()) throw std::invalid_argument("kernel field: the lift must be finite");
    m_lift = lift;
  }
}

void KernelField::addLift(const RowMatrix& dU) {
  if (dU.rows() != m_coef.U.rows() || dU.cols() != m_coef.U.cols())
    throw std::invalid_argument("kernel field: a lift must have one row per sample and one column per control");
  if (!dU.allFinite()) throw std::invalid_argument("kernel field: a lift must be finite");
  if (m_lift.size() == 0) m_lift = RowMatrix::Zero(dU.rows(), dU.cols());
  m_lift += dU;
  m_coef.U += dU;
}

void KernelField::setLift(const RowMatrix& dU) {
  if (m_lift.size() > 0) m_coef.U -= m_lift;
  m_lift.resize(0, 0);
  if (dU.size() > 0) addLift(dU);
}

void KernelField::update(const Weights& W, std::span<const Index> columns) {
  if (!m_interp.ok() && m_interp.evaluable()) {  // restored: factorize K now
    const Points X = m_interp.samples();
    const GaussianKernel kernel = m_interp.kernel();
    const InterpolatorReport r = m_interp.compute(X, kernel, m_interp.mode());
    if (r.status != SolveStatus::Ok)
      throw std::invalid_argument("the kernel matrix of these samples cannot be factorized: " + r.advice);
  }
  if (!m_interp.ok()) throw std::logic_error("kernel field: update() without a successful compute()");
  const bool lifted = m_lift.rows() == W.rows() && m_lift.cols() == W.cols();
  if (!lifted) m_lift.resize(0, 0);
  if (columns.empty() || m_coef.U.rows() != W.rows() || m_coef.U.cols() != W.cols()) {
    m_coef = m_interp.solve(W);
    if (lifted) m_coef.U += m_lift;
  } else {
    m_interp.solveColumns(W, columns, m_coef);
    if (lifted)
      for (const Index c : columns) m_coef.U.col(c) += m_lift.col(c);
  }
}

Weights KernelField::unboundedWeightsAt(const Points& P) const {
  Weights W = m_interp.evaluate(m_coef, P);
  if (m_lines) m_lines->correctWeights(P, W, [&](const Points& Q) { return m_interp.evaluate(m_coef, Q); });
  return W;
}

Weights KernelField::weightsAt(const Points& P) const {
  Weights W = unboundedWeightsAt(P);
  if (m_bound) m_bound->apply(P, W);
  return W;
}

void KernelField::gradientsAt(const Points& P, Weights& dWdx, Weights& dWdy) const {
  m_interp.evaluateGradient(m_coef, P, dWdx, dWdy);
  if (m_lines)
    m_lines->correctGradients(P, dWdx, dWdy, [&](const Points& Q) { return m_interp.evaluate(m_coef, Q); },
                              [&](const Points& Q, Weights& Gx, Weights& Gy) { m_interp.evaluateGradient(m_coef, Q, Gx, Gy); });
  boundGradients(P, dWdx, dWdy, [&](const Points& Q) { return unboundedWeightsAt(Q); });
}

RowMatrix KernelField::coefficientColumns(std::span<const Index> columns) const {
  const std::vector<Index> cols = detail::fieldColumns(columns, controls());
  RowMatrix C(nodes(), static_cast<Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const Index c = cols[k], j = static_cast<Index>(k);
    C.col(j).head(kPolynomialNodes) = m_coef.B.col(c);
    C.col(j).tail(m_coef.U.rows()) = m_coef.U.col(c);
  }
  return C;
}

namespace {

/// E (#P×(3+#S)) from kernel rows R (#P×#S): row p holds the polynomial entries poly(p) (pairs of
/// node, value with node < 3) followed by R's entries shifted by three nodes, each value v of
/// sample j replaced by value(p, j, v).
template <class Poly, class Value>
SparseRowMatrix withPolynomial(const SparseRowMatrix& R, Poly&& poly, Value&& value) {
  constexpr Index kP = KernelField::kPolynomialNodes;
  std::vector<std::vector<std::pair<Index, double>>> head(static_cast<std::size_t>(R.rows()));
  Index extra = 0;
  for (Index p = 0; p < R.rows(); ++p) {
    head[static_cast<std::size_t>(p)] = poly(p);
    extra += static_cast<Index>(head[static_cast<std::size_t>(p)].size());
  }
  SparseRowMatrix E(R.rows(), R.cols() + kP);
  E.resizeNonZeros(R.nonZeros() + extra);
  auto* outer = E.outerIndexPtr();
  auto* inner = E.innerIndexPtr();
  double* val = E.valuePtr();
  Index k = 0;
  outer[0] = 0;
  for (Index p = 0; p < R.rows(); ++p) {
    for (const auto& [node, v] : head[static_cast<std::size_t>(p)]) {
      inner[k] = static_cast<SparseRowMatrix::StorageIndex>(node);
      val[k++] = v;
    }
    for (SparseRowMatrix::InnerIterator it(R, p); it; ++it) {
      inner[k] = static_cast<SparseRowMatrix::StorageIndex>(it.col() + kP);
      val[k++] = value(p, it.col(), it.value());
    }
    outer[p + 1] = static_cast<SparseRowMatrix::StorageIndex>(k);
  }
  return E;
}

}  // namespace

SparseRowMatrix KernelField::evaluationOperator(const Points& P) const {
  if (!m_interp.evaluable()) throw std::logic_error("kernel field: evaluationOperator() without a successful compute()");
  if (!m_lines) return baseEvaluation(P);
  return m_lines->evaluation(P, baseEvaluation(P), [&](const Points& Q) { return baseEvaluation(Q); });
}

void KernelField::gradientOperators(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const {
  if (!m_interp.evaluable()) throw std::logic_error("kernel field: gradientOperators() without a successful compute()");
  baseGradients(P, Ex, Ey);
  if (m_lines)
    m_lines->gradients(P, Ex, Ey, [&](const Points& Q) { return baseEvaluation(Q); },
                       [&](const Points& Q, SparseRowMatrix& Gx, SparseRowMatrix& Gy) { baseGradients(Q, Gx, Gy); });
}

SparseRowMatrix KernelField::baseEvaluation(const Points& P) const {
  const SparseRowMatrix R = kernelRows(m_interp.samples(), P, m_interp.kernel(), &m_interp.widths());
  return withPolynomial(
      R, [&](Index p) { return std::vector<std::pair<Index, double>>{{0, 1.0}, {1, P(p, 0)}, {2, P(p, 1)}}; },
      [](Index, Index, double v) { return v; });
}

void KernelField::baseGradients(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const {
  if (m_interp.kernel().variable()) {  // the Gibbs kernel's gradient (kernelGradientRows)
    SparseRowMatrix Gx, Gy;
    kernelGradientRows(m_interp.samples(), P, m_interp.kernel(), Gx, Gy, &m_interp.widths());
    Ex = withPolynomial(
        Gx, [](Index) { return std::vector<std::pair<Index, double>>{{1, 1.0}}; }, [](Index, Index, double v) { return v; });
    Ey = withPolynomial(
        Gy, [](Index) { return std::vector<std::pair<Index, double>>{{2, 1.0}}; }, [](Index, Index, double v) { return v; });
    return;
  }
  const SparseRowMatrix R = kernelRows(m_interp.samples(), P, m_interp.kernel(), &m_interp.widths());
  const Points& X = m_interp.samples();
  const double inv2 = 1.0 / (m_interp.kernel().sigma * m_interp.kernel().sigma);
  // ∇k(p, x_j) = −k(p, x_j)(p − x_j)/σ² (3.42); ∇[1 x y] = (0, 1, 0), (0, 0, 1).
  Ex = withPolynomial(
      R, [](Index) { return std::vector<std::pair<Index, double>>{{1, 1.0}}; },
      [&](Index p, Index j, double v) { return -v * inv2 * (P(p, 0) - X(j, 0)); });
  Ey = withPolynomial(
      R, [](Index) { return std::vector<std::pair<Index, double>>{{2, 1.0}}; },
      [&](Index p, Index j, double v) { return -v * inv2 * (P(p, 1) - X(j, 1)); });
}

}  // namespace kc
