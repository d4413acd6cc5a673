#include "kc/core/field/line_correction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include <Eigen/QR>

#include "kc/core/parallel.h"
#include "kc/core/structure/lines.h"

namespace kc {
namespace {

/// Rows of a sparse matrix built one at a time from sums of scaled sparse rows.
class RowBuilder {
 public:
  explicit RowBuilder(Index cols) : m_dense(static_cast<std::size_t>(cols), 0.0), m_seen(static_cast<std::size_t>(cols), 0) {}
  void addRow(const SparseRowMatrix& M, Index r, double scale) {
    if (scale == 0.0) return;
    for (SparseRowMatrix::InnerIterator it(M, r); it; ++it) touch(it.col(), scale * it.value());
  }
  /// The accumulated row as sorted (column, value) pairs; resets the builder.
  void take(std::vector<std::pair<Index, double>>& out) {
    std::sort(m_cols.begin(), m_cols.end());
    out.clear();
    for (const Index c : m_cols) {
      out.emplace_back(c, m_dense[static_cast<std::size_t>(c)]);
      m_dense[static_cast<std::size_t>(c)] = 0.0;
      m_seen[static_cast<std::size_t>(c)] = 0;
    }
    m_cols.clear();
  }

 private:
  void touch(Index c, double v) {
    const auto u = static_cast<std::size_t>(c);
    if (!m_seen[u]) {
      m_seen[u] = 1;
      m_cols.push_back(c);
    }
    m_dense[u] += v;
  }
  std::vector<double> m_dense;
  std::vector<char> m_seen;
  std::vector<Index> m_cols;
};

/// A #rows × cols row-major matrix from per-row (column, value) lists.
SparseRowMatrix fromRows(const std::vector<std::vector<std::pair<Index, double>>>& rows, Index cols) {
  Index nnz = 0;
  for (const auto& r : rows) nnz += static_cast<Index>(r.size());
  SparseRowMatrix M(static_cast<Index>(rows.size()), cols);
  M.resizeNonZeros(nnz);
  auto* outer = M.outerIndexPtr();
  auto* inner = M.innerIndexPtr();
  double* val = M.valuePtr();
  Index k = 0;
  outer[0] = 0;
  for (std::size_t p = 0; p < rows.size(); ++p) {
    for (const auto& [c, v] : rows[p]) {
      inner[k] = static_cast<SparseRowMatrix::StorageIndex>(c);
      val[k++] = v;
    }
    outer[p + 1] = static_cast<SparseRowMatrix::StorageIndex>(k);
  }
  return M;
}

/// Row r of M as (column, value) pairs.
std::vector<std::pair<Index, double>> rowOf(const SparseRowMatrix& M, Index r) {
  std::vector<std::pair<Index, double>> out;
  for (SparseRowMatrix::InnerIterator it(M, r); it; ++it) out.emplace_back(it.col(), it.value());
  return out;
}

}  // namespace

LineCorrection::LineCorrection(const Cage& cage, std::span<const StructureLine> lines, std::span<const LineContact> contacts,
                               double sigma, std::span<const Points> barriers)
    : m_cage(cage), m_edges(loopEdges(cage)) {
  if (!hasInterior(cage) || m_edges.empty()) throw std::invalid_argument("line correction: the cage has no interior");
  if (!(sigma > 0.0) || !std::isfinite(sigma)) throw std::invalid_argument("line correction: sigma must be positive");
  for (const Points& P : barriers) {
    if (P.rows() < 3 || P.cols() != 2) throw std::invalid_argument("line correction: a barrier needs at least 3 points");
    m_barriers.push_back(Cage::polygon(P));
  }
  const Index n = static_cast<Index>(lines.size());
  for (Index k = 0; k < n; ++k) {
    const StructureLine& l = lines[static_cast<std::size_t>(k)];
    if (!(l.length() > 0.0)) throw std::invalid_argument("line correction: lines[" + std::to_string(k) + "] has zero length");
    m_a.push_back(l.a);
    m_b.push_back(l.b);
    m_reach.push_back(std::max(kLineCorrectionLength * l.length(), kLineCorrectionSigmas * sigma));
  }
  m_sources.resize(2 * n, 2);
  for (Index k = 0; k < n; ++k) {
    m_sources.row(2 * k) = m_a[static_cast<std::size_t>(k)].transpose();
    m_sources.row(2 * k + 1) = m_b[static_cast<std::size_t>(k)].transpose();
  }
  m_coupling = parallelCoupling(lines);
  if (!contacts.empty()) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Index>(contacts.size()), 2 * n);
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      const LineContact& t = contacts[c];
      const Index r = static_cast<Index>(c), k = static_cast<Index>(t.k), l = static_cast<Index>(t.l);
      A(r, 2 * k) += 1.0 - t.tk;
      A(r, 2 * k + 1) += t.tk;
      A(r, 2 * l) -= 1.0 - t.tl;
      A(r, 2 * l + 1) -= t.tl;
    }
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
    // Three lines through one point repeat a contact: rank < #contacts, which A⁺ handles.
    const Eigen::MatrixXd contactsMap = Eigen::MatrixXd::Identity(2 * n, 2 * n) - cod.pseudoInverse() * A;
    m_coupling = contactsMap * m_coupling;
  }
}

Eigen::MatrixXd LineCorrection::parallelCoupling(std::span<const StructureLine> lines) {
  const Index n = static_cast<Index>(lines.size());
  std::map<int, std::vector<Index>> groups;
  for (Index k = 0; k < n; ++k)
    if (lines[static_cast<std::size_t>(k)].group >= 0) groups[lines[static_cast<std::size_t>(k)].group].push_back(k);
  Index sources = 2 * n;
  for (const auto& [g, members] : groups) sources += members.size() >= 2 ? 2 * static_cast<Index>(members.size()) : 0;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * n, sources);
  M.leftCols(2 * n).setIdentity();
  Index next = 2 * n;
  m_sources.conservativeResize(sources, 2);
  for (const auto& [g, members] : groups) {
    if (members.size() < 2) continue;
    const auto first = static_cast<std::size_t>(members[0]);
    const Vec2 u0 = (lines[first].b - lines[first].a).normalized();
    double total = 0.0;
    Vec2 mean = Vec2::Zero();
    for (const Index k : members) {
      const StructureLine& l = lines[static_cast<std::size_t>(k)];
      const Vec2 u = (l.b - l.a).normalized();
      const double s = u.dot(u0) < 0.0 ? -1.0 : 1.0, L2 = l.length() * l.length();
      mean += L2 * s * u;
      total += L2;
    }
    mean /= total;
    // Coefficient rows over the sources: d̂_l, r_l, then d.
    const Index count = static_cast<Index>(members.size());
    std::vector<Eigen::RowVectorXd> r(static_cast<std::size_t>(count));
    Eigen::RowVectorXd d = Eigen::RowVectorXd::Zero(sources);
    std::vector<double> sign(static_cast<std::size_t>(count)), length(sign.size());
    for (Index q = 0; q < count; ++q) {
      const Index k = members[static_cast<std::size_t>(q)];
      const StructureLine& l = lines[static_cast<std::size_t>(k)];
      const Vec2 u = (l.b - l.a).normalized();
      const double s = u.dot(u0) < 0.0 ? -1.0 : 1.0, L = l.length();
      const Vec2 offset = u - s * mean, middle = 0.5 * (l.a + l.b);
      m_sources.row(next) = (middle + 0.5 * offset).transpose();
      m_sources.row(next + 1) = (middle - 0.5 * offset).transpose();
      Eigen::RowVectorXd rq = Eigen::RowVectorXd::Zero(sources), dhat = Eigen::RowVectorXd::Zero(sources);
      rq(next) = 1.0;
      rq(next + 1) = -1.0;
      dhat(2 * k) = -1.0 / L;
      dhat(2 * k + 1) = 1.0 / L;
      d += (L * L * s / total) * (dhat - rq);
      r[static_cast<std::size_t>(q)] = rq;
      sign[static_cast<std::size_t>(q)] = s;
      length[static_cast<std::size_t>(q)] = L;
      next += 2;
    }
    for (Index q = 0; q < count; ++q) {
      const Index k = members[static_cast<std::size_t>(q)];
      const double L = length[static_cast<std::size_t>(q)];
      const Eigen::RowVectorXd dl = sign[static_cast<std::size_t>(q)] * d + r[static_cast<std::size_t>(q)];
      Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(sources);
      sum(2 * k) = 1.0;
      sum(2 * k + 1) = 1.0;
      M.row(2 * k) = 0.5 * (sum - L * dl);
      M.row(2 * k + 1) = 0.5 * (sum + L * dl);
    }
  }
  return M;
}

bool LineCorrection::gammas(const Vec2& x, std::vector<double>& gamma, std::vector<Vec2>* gradient) const {
  const std::size_t n = m_a.size();
  gamma.assign(n, 0.0);
  if (gradient) gradient->assign(n, Vec2::Zero());
  // Per line within reach: d² = |x − f|², ψ, and their gradients 2(x − f), ψ'.
  std::vector<std::size_t> near;
  std::vector<double> d2, psi;
  std::vector<Vec2> gd2, gpsi;
  for (std::size_t k = 0; k < n; ++k) {
    const double r2 = m_reach[k] * m_reach[k];
    const Vec2 v = x - closestPointOnSegment(x, m_a[k], m_b[k]);
    const double dk = v.squaredNorm();
    if (dk >= r2) continue;
    const double s = 1.0 - dk / r2;
    near.push_back(k);
    d2.push_back(dk);
    psi.push_back(s * s);
    gd2.push_back(2.0 * v);
    gpsi.push_back(-2.0 * s / r2 * 2.0 * v);
  }
  if (near.empty() || !insideCage(m_cage, x)) return false;
  for (const Cage& b : m_barriers)
    if (insideCage(b, x)) return false;
  double A = 0.0;  // Σ_edges |x − edge|⁻² over the cage and the barriers
  Vec2 gA = Vec2::Zero();
  auto addEdge = [&](const Vec2& a, const Vec2& b) {
    const Vec2 v = x - closestPointOnSegment(x, a, b);
    const double e = v.squaredNorm();
    if (e == 0.0) return false;  // on the cage or a barrier: no correction
    A += 1.0 / e;
    gA -= 2.0 * v / (e * e);
    return true;
  };
  for (const auto& [i, j] : m_edges)
    if (!addEdge(m_cage.C.row(i).transpose(), m_cage.C.row(j).transpose())) return false;
  for (const Cage& b : m_barriers)
    for (Index i = 0; i < b.size(); ++i)
      if (!addEdge(b.C.row(i).transpose(), b.C.row((i + 1) % b.size()).transpose())) return false;
  const double D = 1.0 / A;
  const Vec2 gD = -gA / (A * A);
  // γ_k = (ψ_k/d_k²) / (Σ_j ψ_j/d_j² + 1/D), multiplied through by D·Π_j d_j² (finite on a line):
  // N_k = ψ_k D Π_{j≠k} d_j²,  γ_k = N_k / (Σ_j N_j + Π_j d_j²).
  const std::size_t q = near.size();
  auto productExcept = [&](std::size_t skipA, std::size_t skipB) {
    double p = 1.0;
    for (std::size_t j = 0; j < q; ++j)
      if (j != skipA && j != skipB) p *= d2[j];
    return p;
  };
  auto gradProductExcept = [&](std::size_t skip) {  // ∇ Π_{j≠skip} d_j²
    Vec2 g = Vec2::Zero();
    for (std::size_t j = 0; j < q; ++j)
      if (j != skip) g += gd2[j] * productExcept(skip, j);
    return g;
  };
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<double> N(q);
  std::vector<Vec2> gN(q);
  double S = productExcept(kNone, kNone);
  Vec2 gS = gradProductExcept(kNone);
  for (std::size_t k = 0; k < q; ++k) {
    const double others = productExcept(k, kNone);
    N[k] = psi[k] * D * others;
    gN[k] = gpsi[k] * D * others + psi[k] * gD * others + psi[k] * D * gradProductExcept(k);
    S += N[k];
    gS += gN[k];
  }
  if (S > 0.0) {
    for (std::size_t k = 0; k < q; ++k) {
      gamma[near[k]] = N[k] / S;
      if (gradient) (*gradient)[near[k]] = (gN[k] * S - N[k] * gS) / (S * S);
    }
    return true;
  }
  // On two or more lines at once (where they meet, their corrections agree): share equally.
  std::size_t on = 0;
  for (std::size_t k = 0; k < q; ++k) on += d2[k] == 0.0;
  for (std::size_t k = 0; k < q; ++k)
    if (d2[k] == 0.0) gamma[near[k]] = 1.0 / static_cast<double>(on);
  return on > 0;
}

void LineCorrection::terms(const Vec2& x, std::vector<Term>& out, bool gradient) const {
  std::vector<double> g;
  std::vector<Vec2> dg;
  if (!gammas(x, g, gradient ? &dg : nullptr)) return;
  for (std::size_t k = 0; k < g.size(); ++k) {
    if (g[k] == 0.0) continue;
    Term t;
    t.line = static_cast<Index>(k);
    t.gamma = g[k];
    const Vec2 u = m_b[k] - m_a[k];
    const double raw = (x - m_a[k]).dot(u) / u.squaredNorm();
    t.t = std::clamp(raw, 0.0, 1.0);
    if (gradient) {
      t.gradGamma = dg[k];
      if (raw > 0.0 && raw < 1.0) t.gradT = u / u.squaredNorm();
    }
    out.push_back(t);
  }
}

SparseRowMatrix LineCorrection::endRows(const Evaluate& evaluate) const {
  const SparseRowMatrix E = evaluate(m_sources);
  RowBuilder b(E.cols());
  std::vector<std::vector<std::pair<Index, double>>> rows(static_cast<std::size_t>(m_coupling.rows()));
  for (Index r = 0; r < m_coupling.rows(); ++r) {
    for (Index c = 0; c < m_coupling.cols(); ++c) b.addRow(E, c, m_coupling(r, c));
    b.take(rows[static_cast<std::size_t>(r)]);
  }
  return fromRows(rows, E.cols());
}

namespace {

/// The terms of every row of P and the feet f_k (rows of F) they need, in order.
struct Corrections {
  std::vector<std::vector<LineCorrection::Term>> terms;  // per row of P
  Points feet;                                          // one per term, in row order
};

Corrections correctionsAt(const LineCorrection& lc, const Points& P, const std::vector<Vec2>& a,
                                 const std::vector<Vec2>& b, bool gradient) {
  Corrections c;
  c.terms.resize(static_cast<std::size_t>(P.rows()));
  parallelFor(P.rows(), [&](Index p) { lc.terms(P.row(p).transpose(), c.terms[static_cast<std::size_t>(p)], gradient); }, 256);
  Index count = 0;
  for (const auto& t : c.terms) count += static_cast<Index>(t.size());
  c.feet.resize(count, 2);
  Index f = 0;
  for (const auto& ts : c.terms)
    for (const auto& t : ts) {
      const auto k = static_cast<std::size_t>(t.line);
      c.feet.row(f++) = ((1.0 - t.t) * a[k] + t.t * b[k]).transpose();
    }
  return c;
}

}  // namespace

SparseRowMatrix LineCorrection::evaluation(const Points& P, const SparseRowMatrix& E, const Evaluate& evaluate) const {
  const Corrections c = correctionsAt(*this, P, m_a, m_b, false);
  if (c.feet.rows() == 0) return E;
  const SparseRowMatrix EF = evaluate(c.feet), V = endRows(evaluate);
  std::vector<std::vector<std::pair<Index, double>>> rows(static_cast<std::size_t>(P.rows()));
  RowBuilder builder(E.cols());
  Index f = 0;
  for (Index p = 0; p < P.rows(); ++p) {
    const auto& ts = c.terms[static_cast<std::size_t>(p)];
    if (ts.empty()) {
      rows[static_cast<std::size_t>(p)] = rowOf(E, p);
      continue;
    }
    builder.addRow(E, p, 1.0);
    for (const Term& t : ts) {  // − γ (E(f) − (1 − t) V_a − t V_b)
      builder.addRow(EF, f++, -t.gamma);
      builder.addRow(V, 2 * t.line, t.gamma * (1.0 - t.t));
      builder.addRow(V, 2 * t.line + 1, t.gamma * t.t);
    }
    builder.take(rows[static_cast<std::size_t>(p)]);
  }
  return fromRows(rows, E.cols());
}

void LineCorrection::gradients(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey, const Evaluate& evaluate,
                               const Gradients& gradients) const {
  const Corrections c = correctionsAt(*this, P, m_a, m_b, true);
  if (c.feet.rows() == 0) return;
  const SparseRowMatrix EF = evaluate(c.feet), V = endRows(evaluate);
  SparseRowMatrix FX, FY;
  gradients(c.feet, FX, FY);
  std::vector<std::vector<std::pair<Index, double>>> rx(static_cast<std::size_t>(P.rows())), ry(rx.size());
  RowBuilder builder(Ex.cols());
  for (int axis = 0; axis < 2; ++axis) {
    const SparseRowMatrix& G = axis == 0 ? Ex : Ey;
    auto& rows = axis == 0 ? rx : ry;
    Index f = 0;
    for (Index p = 0; p < P.rows(); ++p) {
      const auto& ts = c.terms[static_cast<std::size_t>(p)];
      if (ts.empty()) {
        rows[static_cast<std::size_t>(p)] = rowOf(G, p);
        continue;
      }
      builder.addRow(G, p, 1.0);
      for (const Term& t : ts) {
        // ∂/∂x [γ D],  D = E(f) − (1 − t) V_a − t V_b,  ∂D/∂x = ∂t/∂x (u·∇E(f) − V_b + V_a)
        const auto k = static_cast<std::size_t>(t.line);
        const double gg = t.gradGamma[axis], gt = t.gamma * t.gradT[axis];
        const Vec2 u = m_b[k] - m_a[k];
        builder.addRow(EF, f, -gg);
        builder.addRow(V, 2 * t.line, gg * (1.0 - t.t) - gt);
        builder.addRow(V, 2 * t.line + 1, gg * t.t + gt);
        builder.addRow(FX, f, -gt * u.x());
        builder.addRow(FY, f, -gt * u.y());
        ++f;
      }
      builder.take(rows[static_cast<std::size_t>(p)]);
    }
  }
  const Index cols = Ex.cols();
  Ex = fromRows(rx, cols);
  Ey = fromRows(ry, cols);
}

void LineCorrection::correctWeights(const Points& P, Weights& W, const EvaluateWeights& evaluate) const {
  const Corrections c = correctionsAt(*this, P, m_a, m_b, false);
  if (c.feet.rows() == 0) return;
  const Weights WF = evaluate(c.feet), V = m_coupling * evaluate(m_sources);
  Index f = 0;
  for (Index p = 0; p < P.rows(); ++p)
    for (const Term& t : c.terms[static_cast<std::size_t>(p)]) {
      W.row(p) -= t.gamma * (WF.row(f++) - (1.0 - t.t) * V.row(2 * t.line) - t.t * V.row(2 * t.line + 1));
    }
}

void LineCorrection::correctGradients(const Points& P, Weights& dWdx, Weights& dWdy, const EvaluateWeights& evaluate,
                                      const WeightGradients& gradients) const {
  const Corrections c = correctionsAt(*this, P, m_a, m_b, true);
  if (c.feet.rows() == 0) return;
  const Weights WF = evaluate(c.feet), V = m_coupling * evaluate(m_sources);
  Weights FX, FY;
  gradients(c.feet, FX, FY);
  Index f = 0;
  for (Index p = 0; p < P.rows(); ++p)
    for (const Term& t : c.terms[static_cast<std::size_t>(p)]) {
      // ∇[γ D], D = w(f) − (1 − t) v_a − t v_b, ∇D = ∇t (u·∇w(f) − v_b + v_a)
      const auto k = static_cast<std::size_t>(t.line);
      const Vec2 u = m_b[k] - m_a[k];
      const Eigen::RowVectorXd D = WF.row(f) - (1.0 - t.t) * V.row(2 * t.line) - t.t * V.row(2 * t.line + 1);
      const Eigen::RowVectorXd along = u.x() * FX.row(f) + u.y() * FY.row(f) - V.row(2 * t.line + 1) + V.row(2 * t.line);
      dWdx.row(p) -= t.gradGamma.x() * D + t.gamma * t.gradT.x() * along;
      dWdy.row(p) -= t.gradGamma.y() * D + t.gamma * t.gradT.y() * along;
      ++f;
    }
}

}  // namespace kc
