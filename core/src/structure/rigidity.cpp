#include "kc/core/structure/rigidity.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "kc/core/spatial_grid.h"
#include "../huge_pages.h"
#include "rigidity_admm.h"

namespace kc {
namespace {

std::string regionName(std::size_t k) { return "rigid[" + std::to_string(k) + "]"; }

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Indices of the samples within `radius` of any sample in `from` (sorted), marking them in `mark`.
std::vector<Index> within(const SpatialGrid& grid, const Points& X, std::span<const Index> from, double radius) {
  std::vector<char> mark(static_cast<std::size_t>(X.rows()), 0);
  for (Index i : from) grid.forEachWithin(X.row(i).transpose(), radius, [&](Index j, double) { mark[std::size_t(j)] = 1; });
  std::vector<Index> out;
  for (Index j = 0; j < X.rows(); ++j)
    if (mark[std::size_t(j)]) out.push_back(j);
  return out;
}

Points rowsOf(const Points& X, std::span<const Index> idx) {
  Points P(Index(idx.size()), 2);
  for (std::size_t k = 0; k < idx.size(); ++k) P.row(Index(k)) = X.row(idx[k]);
  return P;
}

/// The node columns of the field's gradient operators ∂E/∂x, ∂E/∂y at P (KernelField::
/// gradientOperators: ∇k(p, x_j) = −k(p, x_j)(p − x_j)/σ², thesis 3.42), from the kernel rows of
/// the nodes XN alone (a #P×|N| matrix, node = position in N) instead of all samples' columns.
void nodeGradients(const Points& XN, const Points& P, const GaussianKernel& kernel, SparseRowMatrix& Gx, SparseRowMatrix& Gy) {
  kernelGradientRows(XN, P, kernel, Gx, Gy);
}

/// Adds Σ_p w_p M_pᵀ M_p (M's rows, column indices ascending) to the lower triangle of the dense H:
/// one pass over the rows' non-zeros, for Gram matrices of short rows (a kernel row has a few dozen
/// node entries), where a sparse-sparse product spends most of its time merging index lists.
void addRowGram(const SparseRowMatrix& M, const Eigen::VectorXd& w, Eigen::MatrixXd& H) {
  const auto* outer = M.outerIndexPtr();
  const auto* inner = M.innerIndexPtr();
  const double* value = M.valuePtr();
  for (Index p = 0; p < M.rows(); ++p) {
    if (w(p) == 0.0) continue;
    for (auto a = outer[p]; a < outer[p + 1]; ++a) {
      const double va = w(p) * value[a];
      double* column = H.col(inner[a]).data();
      for (auto b = a; b < outer[p + 1]; ++b) column[inner[b]] += va * value[b];
    }
  }
}

/// H = κ (GxᵀDρGx + GyᵀDρGy) + Krᵀ Df Kr (|N|×|N|). Up to `denseNodes` nodes it is accumulated in
/// a dense matrix (the solver factorizes it dense there anyway), beyond by sparse products.
SparseMatrix rigidityHessian(const SparseRowMatrix& Gx, const SparseRowMatrix& Gy, const Eigen::VectorXd& rhoQ,
                             const SparseRowMatrix& Kr, const Eigen::VectorXd& fid, double kappa, Index denseNodes) {
  const Index n = Kr.cols();
  if (n <= denseNodes) {
    Eigen::MatrixXd H(n, n);  // the lower triangle only (the upper half's memory stays untouched)
    detail::preferHugePages(H);
    for (Index j = 0; j < n; ++j) H.col(j).tail(n - j).setZero();
    const Eigen::VectorXd w = kappa * rhoQ;
    addRowGram(Gx, w, H);
    addRowGram(Gy, w, H);
    addRowGram(Kr, fid, H);
    SparseMatrix S(n, n);  // both triangles, column by column: H(i, j) = H(j, i) above the diagonal
    for (Index j = 0; j < n; ++j) {
      S.startVec(j);
      for (Index i = 0; i < n; ++i)
        if (const double v = i >= j ? H(i, j) : H(j, i); v != 0.0) S.insertBack(i, j) = v;
    }
    S.finalize();
    return S;
  }
  const SparseMatrix X = Gx, Y = Gy, K = Kr;
  const SparseMatrix DGx = rhoQ.asDiagonal() * X, DGy = rhoQ.asDiagonal() * Y, DK = fid.asDiagonal() * K;
  return kappa * (SparseMatrix(X.transpose()) * DGx + SparseMatrix(Y.transpose()) * DGy) + SparseMatrix(K.transpose()) * DK;
}

/// Quadrature points of the rigidity energy (5.12) over the painted region: the points of a grid of
/// spacing h whose nearest sample (within 2h + the sample spacing) is painted, each with that
/// sample's ρ scaled so that Σ_q ρ_q = Σ_{i∈I} ρ_i (the scale of the per-sample sum 5.16). Denser
/// than the samples: the gradients of a kernel expansion are not controlled between samples when
/// the energy is evaluated only at them.
void quadrature(const SpatialGrid& grid, const Points& X, std::span<const double> rho, std::span<const Index> region, double h,
                double search, Points& Q, Eigen::VectorXd& rhoQ) {
  Eigen::Vector2d lo = X.row(region[0]).transpose(), hi = lo;
  double total = 0.0;
  for (Index i : region) {
    lo = lo.cwiseMin(X.row(i).transpose());
    hi = hi.cwiseMax(X.row(i).transpose());
    total += rho[std::size_t(i)];
  }
  lo.array() -= search;
  hi.array() += search;
  std::vector<Vec2> pts;
  std::vector<double> r;
  for (double y = lo.y(); y <= hi.y(); y += h)
    for (double x = lo.x(); x <= hi.x(); x += h) {
      Index best = -1;
      double bestD = std::numeric_limits<double>::infinity();
      grid.forEachWithin(Vec2(x, y), search, [&](Index j, double d2) {
        if (d2 < bestD) bestD = d2, best = j;
      });
      if (best >= 0 && rho[std::size_t(best)] > 0.0) {
        pts.emplace_back(x, y);
        r.push_back(rho[std::size_t(best)]);
      }
    }
  Q.resize(Index(pts.size()), 2);
  rhoQ.resize(Index(pts.size()));
  double sum = 0.0;
  for (std::size_t k = 0; k < pts.size(); ++k) Q.row(Index(k)) = pts[k].transpose(), rhoQ(Index(k)) = r[k], sum += r[k];
  if (sum > 0.0) rhoQ *= total / sum;
}

}  // namespace

bool insidePolygon(const Points& polygon, const Vec2& p) {
  const Index n = polygon.rows();
  bool in = false;
  for (Index i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a = polygon.row(j).transpose(), b = polygon.row(i).transpose();
    if (pointSegmentDistance(p, a, b) <= 1e-12 * (1.0 + p.cwiseAbs().maxCoeff())) return true;
    if ((b.y() > p.y()) != (a.y() > p.y()) && p.x() < (a.x() - b.x()) * (p.y() - b.y()) / (a.y() - b.y()) + b.x()) in = !in;
  }
  return in;
}

Vec2 polygonCentroid(const Points& P) {
  double a = 0.0;
  Vec2 c = Vec2::Zero();
  for (Index i = 0, n = P.rows(); i < n; ++i) {
    const Vec2 p = P.row(i).transpose(), q = P.row((i + 1) % n).transpose();
    const double cr = cross(p, q);
    a += cr;
    c += cr * (p + q);
  }
  return c / (3.0 * a);
}

void validateRigidRegions(const Cage& cage, std::span<const RigidRegion> regions) {
  if (!regions.empty() && !cage.closed && cage.edges.empty())
    throw std::invalid_argument("rigid[0]: an open cage has no interior for a rigid region");
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const std::string name = regionName(k);
    const Points& P = regions[k].polygon;
    const double s = regions[k].strength;
    if (!std::isfinite(s) || s < 0.0 || s > 1.0)
      throw std::invalid_argument(name + ": strength must be a number in [0, 1] (got " + std::to_string(s) + ")");
    if (P.rows() < 3) throw std::invalid_argument(name + ": the polygon needs at least 3 points (got " + std::to_string(P.rows()) + ")");
    if (!P.allFinite()) throw std::invalid_argument(name + ": the polygon has a coordinate that is not a finite number");
    const Index n = P.rows();
    for (Index i = 0; i < n; ++i)
      if ((P.row(i) - P.row((i + 1) % n)).norm() == 0.0)
        throw std::invalid_argument(name + ": polygon points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) + " are the same point");
    if (std::abs(signedArea(P)) <= 1e-9 * (1.0 + P.cwiseAbs().maxCoeff()))
      throw std::invalid_argument(name + ": the polygon has no area");
    for (Index i = 0; i < n; ++i)
      if (!insideCage(cage, P.row(i).transpose()))
        throw std::invalid_argument(name + ": polygon point " + std::to_string(i) + " is outside the cage");
    for (Index i = 0; i < n; ++i) {
      const Vec2 a = P.row(i).transpose(), b = P.row((i + 1) % n).transpose();
      for (Index j = i + 1; j < n; ++j) {
        const Vec2 c = P.row(j).transpose(), d = P.row((j + 1) % n).transpose();
        const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
        if (!adjacent && segmentSegmentDistance(a, b, c, d) == 0.0)
          throw std::invalid_argument(name + ": the polygon intersects itself (edges " + std::to_string(i) + " and " + std::to_string(j) + ")");
        if (adjacent) {  // folding back along the previous edge
          const Vec2 shared = j == i + 1 ? b : a, u = (j == i + 1 ? a : b) - shared, v = (j == i + 1 ? d : c) - shared;
          if (std::abs(cross(u, v)) <= 1e-12 * u.norm() * v.norm() && u.dot(v) > 0.0)
            throw std::invalid_argument(name + ": the polygon intersects itself (edges " + std::to_string(i) + " and " + std::to_string(j) + " overlap)");
        }
      }
      if (segmentCrossesCage(cage, a, b))
        throw std::invalid_argument(name + ": polygon edge " + std::to_string(i) + " crosses a cage edge");
    }
  }
}

std::vector<double> rigidityOfRegions(const Points& X, std::span<const RigidRegion> regions) {
  std::vector<double> rho(static_cast<std::size_t>(X.rows()), 0.0);
  for (const RigidRegion& r : regions) {
    const Eigen::Vector2d lo = r.polygon.colwise().minCoeff().transpose(), hi = r.polygon.colwise().maxCoeff().transpose();
    for (Index i = 0; i < X.rows(); ++i) {
      const Vec2 p = X.row(i).transpose();
      if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
      if (insidePolygon(r.polygon, p)) rho[std::size_t(i)] = std::max(rho[std::size_t(i)], r.strength);
    }
  }
  return rho;
}

std::vector<Index> rigidityZone(const KernelField& field, std::span<const double> rho, const RigidityOptions& options) {
  const Points& X = field.interpolator().samples();
  if (Index(rho.size()) != X.rows()) throw std::invalid_argument("rigidityZone: rho needs one entry per sample");
  std::vector<Index> region;
  for (Index i = 0; i < X.rows(); ++i)
    if (rho[std::size_t(i)] > 0.0) region.push_back(i);
  if (region.empty()) return {};
  const GaussianKernel& k = field.interpolator().kernel();
  const double radius = options.reach * k.sigma + k.cutoff();
  return within(SpatialGrid(X, radius), X, region, radius);
}

RigidityReport makeRigid(KernelField& field, const Points& C, std::span<const double> rho, const std::vector<char>& keep,
                         Weights& W, const RigidityOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RigidityReport rep;
  const KernelInterpolator& interp = field.interpolator();
  const Points& X = interp.samples();
  const Index n = X.rows(), m = W.cols();
  if (Index(rho.size()) != n || Index(keep.size()) != n || W.rows() != n || C.rows() != m || C.cols() != 2)
    throw std::invalid_argument("makeRigid: rho, keep and W need one entry per sample and C one row per control");
  std::vector<Index> region;
  for (Index i = 0; i < n; ++i) {
    const double r = rho[std::size_t(i)];
    if (!(r >= 0.0 && r <= 1.0)) throw std::invalid_argument("makeRigid: rigidity must lie in [0, 1]");
    if (r > 0.0) region.push_back(i);
  }
  rep.region = Index(region.size());
  if (region.empty()) return rep;
  const GaussianKernel& kernel = interp.kernel();
  const double sigma = kernel.sigma, s2 = sigma * sigma, theta = kernel.cutoff();

  // Nodes N (coefficients that change) and changed samples Ch (within θ of a node).
  const SpatialGrid grid(X, theta);
  const std::vector<Index> N = within(grid, X, region, options.reach * sigma);
  const std::vector<Index> Ch = within(grid, X, N, theta);
  std::vector<Index> nodeOf(static_cast<std::size_t>(n), -1);
  for (std::size_t k = 0; k < N.size(); ++k) nodeOf[std::size_t(N[k])] = Index(k);
  const Index nN = Index(N.size()), nCh = Index(Ch.size());
  rep.nodes = nN;

  // Active controls and Z: an orthonormal basis of {v : 1ᵀv = 0, Cᵀv = 0} on them (the rows of ΔU).
  std::vector<Index> active;
  for (Index c = 0; c < m; ++c) {
    double most = 0.0;
    for (Index j : N) most = std::max(most, W(j, c));
    if (most > options.activeWeight) active.push_back(c);
  }
  rep.controls = Index(active.size());
  Eigen::MatrixXd P1(active.size(), 3);
  for (std::size_t k = 0; k < active.size(); ++k) P1.row(Index(k)) << 1.0, C(active[k], 0) / sigma, C(active[k], 1) / sigma;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(P1, Eigen::ComputeFullU);
  const Index rank = svd.rank();
  if (Index(active.size()) <= rank) {
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;  // no freedom: the active controls' weights are fixed by reproduction
  }
  RigidityQp qp;
  qp.Z = RowMatrix::Zero(m, Index(active.size()) - rank);
  for (std::size_t k = 0; k < active.size(); ++k) qp.Z.row(active[k]) = svd.matrixU().row(Index(k)).tail(qp.Z.cols());

  // Operators: K(Ch, N), ∂E/∂x and ∂E/∂y at the region's quadrature points restricted to the nodes.
  Points XI;
  Eigen::VectorXd rhoI;
  quadrature(grid, X, rho, region, options.quadratureStep * sigma, 2.0 * sigma, XI, rhoI);
  const Points XCh = rowsOf(X, Ch), XN = rowsOf(X, N);
  const SparseRowMatrix Kr = kernelRows(XN, XCh, kernel);  // K(Ch, N): the evaluation operator's node columns
  SparseRowMatrix Gx, Gy;
  nodeGradients(XN, XI, kernel, Gx, Gy);
  Weights dWdx, dWdy;
  field.gradientsAt(XI, dWdx, dWdy);

  // Objective (docs/rigidity.md): H = σ² (GxᵀDρGx + GyᵀDρGy) + Krᵀ D(1−ρ) Kr, G = σ² (GxᵀDρ∂xW + GyᵀDρ∂yW).
  Eigen::VectorXd fid(nCh);
  for (Index k = 0; k < nCh; ++k) fid(k) = 1.0 - rho[std::size_t(Ch[std::size_t(k)])];
  const double kappa = options.rigidityWeight * s2;
  qp.H = rigidityHessian(Gx, Gy, rhoI, Kr, fid, kappa, options.solver.maxDenseNodes);
  qp.G = kappa * (Gx.transpose() * (rhoI.asDiagonal() * dWdx) + Gy.transpose() * (rhoI.asDiagonal() * dWdy));
  rep.energyBefore = s2 * (rhoI.asDiagonal() * (dWdx.rowwise().squaredNorm() + dWdy.rowwise().squaredNorm())).sum();

  // Equalities: the held samples, rows scaled to unit length. Exact mode's side condition PᵀΔU = 0
  // is not imposed (docs/rigidity.md): the new data weights are interpolated again, which keeps
  // partition of unity and reproduction for any data that have them at the samples.
  std::vector<Eigen::RowVectorXd> eq;
  const SparseRowMatrix& KrRows = Kr;
  std::vector<Index> constrained;  // rows of Kr bounded below: region samples (and nodes), ΔW ≥ −W⁺
  for (Index k = 0; k < nCh; ++k) {
    const Index i = Ch[std::size_t(k)];
    if (keep[std::size_t(i)]) {  // held: K(h, N) ΔU = 0 ⇔ K(h, N) Y = 0 (Zᵀ has full row rank)
      Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(nN);
      for (SparseRowMatrix::InnerIterator it(KrRows, k); it; ++it) row(it.col()) = it.value();
      if (row.norm() > 0.0) eq.push_back(row), ++rep.held;
    } else if (rho[std::size_t(i)] > 0.0 || (options.boundNodes && nodeOf[std::size_t(i)] >= 0)) {
      constrained.push_back(k);
    }
  }
  qp.A.resize(Index(eq.size()), nN);
  for (std::size_t r = 0; r < eq.size(); ++r) qp.A.row(Index(r)) = eq[r] / eq[r].norm();
  std::vector<Eigen::Triplet<double>> t;
  qp.L.resize(Index(constrained.size()), m);
  for (std::size_t r = 0; r < constrained.size(); ++r) {
    for (SparseRowMatrix::InnerIterator it(KrRows, constrained[r]); it; ++it) t.emplace_back(Index(r), it.col(), it.value());
    qp.L.row(Index(r)) = -W.row(Ch[std::size_t(constrained[r])]).cwiseMax(0.0);
  }
  qp.Kc.resize(Index(constrained.size()), nN);
  qp.Kc.setFromTriplets(t.begin(), t.end());

  const RowMatrix dU = solveRigidityQp(qp, options.solver, &rep.solver);

  // Apply: W(Ch) += K(Ch, N) ΔU, the constrained rows projected onto their bounds (exact
  // non-negativity at the solver's tolerance's cost; docs/rigidity.md, "Large regions"); re-solve
  // the active columns.
  RowMatrix dW = Kr * dU;
  const detail::RowProjection projected = detail::projectRows(qp.Z, qp.L, constrained, dW);
  rep.projectedRows = projected.changed;
  rep.projectionChange = projected.largest;
  rep.minWeight = std::numeric_limits<double>::infinity();
  for (Index k = 0; k < nCh; ++k) {
    const Index i = Ch[std::size_t(k)];
    if (dW.row(k).cwiseAbs().maxCoeff() > 0.0) ++rep.changedRows;
    W.row(i) += dW.row(k);
  }
  for (std::size_t r = 0; r < constrained.size(); ++r) rep.minWeight = std::min(rep.minWeight, W.row(Ch[std::size_t(constrained[r])]).minCoeff());
  const RowMatrix gx = dWdx + Gx * dU, gy = dWdy + Gy * dU;
  rep.energyAfter = s2 * (rhoI.asDiagonal() * (gx.rowwise().squaredNorm() + gy.rowwise().squaredNorm())).sum();
  field.update(W, active);
  rep.columns = active;
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace kc
