// ADMM for local barycentric coordinates (LBC paper, Appendix B), in the null-space form
// W = Y M + H so that W K = B (reproduction, partition of unity) holds at every iterate.
//
// Inner products. The paper's augmented Lagrangian (25) uses plain Frobenius norms. Here the
// constraint X = ∇W is weighted by the triangle areas a_s and W = YM + H by the lumped vertex
// masses m_v (an equivalent problem: the constraints are unchanged, only the penalty's metric is
// that of L²(Ω)). Then
//   step 1: x_i^s = shrink(a, φ_i^s/μ)        (area cancels; eq. 30 with A_s/μ → 1/μ)
//           W = max(0, YM + H − U2)           (eq. 31)
//   step 2: (L_II + M_II) Y = (Gᵀ A P + M_II Q) Mᵀ, P = X̃ + U1 − J, Q = W̃ + U2 − H
//           (L the cotangent stiffness matrix: GᵀAG; X̃, W̃ over-relaxed as in Appendix B)
//   step 3: U1 += X̃ − ∇W_new, U2 += W̃ − (Y_new M + H)   (scaled multipliers U = λ/μ)
//   Since M has orthonormal rows, MᵀM = I − Q1 Q1ᵀ (Q1: orthonormal basis of range(K)), so
//   Y M = (L_II + M_II)⁻¹ (Gᵀ A P + M_II Q) (I − Q1 Q1ᵀ): step 2 solves for all m columns and
//   projects each row; Y itself is never formed.
//   The loop keeps only V1 = X̃ + U1 and V2 = W̃ + U2 (with the iterate and the multipliers):
//   step 3 is U = V − B Z_new, and step 1 of the next iteration follows in the same pass over the
//   vertices and the triangles (no per-triangle right-hand-side array; step 2 gathers Gᵀ A V1).
//   The primal residual is therefore that of step 1's X, W against the Z_new they come from.
// so the Y-system matrix is the same for every μ (adaptive μ costs nothing) and the residuals are
// discretized L² norms, comparable across mesh sizes.
//
// Certificate. Besides the last iterate, the loop keeps averages: of Z over the iterations since
// the previous check, of U1 over every 4th iteration with iteration t weighted by t² (the early
// ones fade out). ADMM's last iterate swings about the optimum (more so over-relaxed); the averages
// settle on it sooner, so at each check the weights are the better of the two projected
// candidates and the lower bound the larger of the two multipliers' bounds. Both are valid
// whatever the averages: any non-negative barycentric weights are a candidate, and the bound
// clips any multiplier into the dual-feasible set. Z's average starts afresh at each check (and
// only after the first): an average reaching back to the harmonic start (non-zero everywhere)
// keeps small tails of it in every weight, which the objective barely sees and the locality
// measures count.
#include "kc/core/lbc/lbc_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>

#include "barycentric_lp.h"
#include "row_block_cholesky.h"
#include "simd.h"
#include "kc/core/lbc/heat_geodesic.h"
#include "kc/core/parallel.h"
#include "kc/core/weights/sample_qp.h"
#include "kc/core/timing.h"

namespace kc {
namespace {

/// Σ_j a_j² in four interleaved partial sums (a fixed order the compiler can vectorize).
inline double sumOfSquares(const double* a, Index n) {
  double p[4] = {0.0, 0.0, 0.0, 0.0};
  Index j = 0;
  for (; j + 4 <= n; j += 4)
    for (int l = 0; l < 4; ++l) p[l] += a[j + l] * a[j + l];
  for (; j < n; ++j) p[0] += a[j] * a[j];
  return (p[0] + p[1]) + (p[2] + p[3]);
}

/// Step 1 of one triangle's m controls (eq. 30) from g = ∇_s W, u = U1_s (x parts, then y parts,
/// 2m each) and the thresholds φ_s/μ: X = shrink(g − u, φ/μ), v ← αX + (1 − α)g + u, r ← X − g.
/// A free function on restrict pointers, so that the loop vectorizes.
inline void shrinkRow(Index m, double alpha, const double* __restrict g, const double* __restrict u,
                      const double* __restrict threshold, double* __restrict v, double* __restrict r) {
  for (Index i = 0; i < m; ++i) {  // (branch-free)
    const double ax = g[i] - u[i], ay = g[m + i] - u[m + i];
    const double len = std::sqrt(ax * ax + ay * ay), thr = threshold[i];
    const double q = 1.0 - thr / len;  // NaN or ≤ 0 where len ≤ thr (len = 0 included): the factor is 0
    const double f = q > 0.0 ? q : 0.0;
    const double xx = f * ax, xy = f * ay;
    v[i] = alpha * xx + (1.0 - alpha) * g[i] + u[i];
    v[m + i] = alpha * xy + (1.0 - alpha) * g[m + i] + u[m + i];
    r[i] = xx - g[i];
    r[m + i] = xy - g[m + i];
  }
}

/// The gradients (gx, gy: m each) of m linear functions on a triangle with corner values f0, f1,
/// f2 and the corners' basis gradients gr (a free function on restrict pointers, so that it vectorizes).
inline void gradientOf(Index m, const std::array<Vec2, 3>& gr, const double* __restrict f0, const double* __restrict f1,
                       const double* __restrict f2, double* __restrict gx, double* __restrict gy) {
  const double x0 = gr[0].x(), x1 = gr[1].x(), x2 = gr[2].x(), y0 = gr[0].y(), y1 = gr[1].y(), y2 = gr[2].y();
  for (Index i = 0; i < m; ++i) gx[i] = x0 * f0[i] + x1 * f1[i] + x2 * f2[i];
  for (Index i = 0; i < m; ++i) gy[i] = y0 * f0[i] + y1 * f1[i] + y2 * f2[i];
}

/// out = a − b (n values).
inline void difference(Index n, const double* __restrict a, const double* __restrict b, double* __restrict out) {
  for (Index i = 0; i < n; ++i) out[i] = a[i] - b[i];
}

/// avg ← avg + rate·(x − avg) (n values).
inline void moveToward(Index n, double rate, const double* __restrict x, double* __restrict avg) {
  for (Index i = 0; i < n; ++i) avg[i] += rate * (x[i] - avg[i]);
}

/// Step 3 at a vertex's m controls from the new affine row zn: u = v − zn, dz = zn − z, z = zn.
inline void affineStep(Index m, const double* __restrict zn, const double* __restrict v, double* __restrict z,
                       double* __restrict u, double* __restrict dz) {
  for (Index i = 0; i < m; ++i) {
    u[i] = v[i] - zn[i];
    dz[i] = zn[i] - z[i];
    z[i] = zn[i];
  }
}

/// Step 1 at a vertex's m controls (eq. 31): W = max(0, z − u), v ← αW + (1 − α)z + u, r ← W − z.
inline void clampRow(Index m, double alpha, const double* __restrict z, const double* __restrict u, double* __restrict v,
                     double* __restrict r) {
  for (Index i = 0; i < m; ++i) {
    const double d = z[i] - u[i], w = d > 0.0 ? d : 0.0;
    v[i] = alpha * w + (1.0 - alpha) * z[i] + u[i];
    r[i] = w - z[i];
  }
}

/// out = y (I − Q Qᵀ) + h for a row y of m values, Q = [q0 q1 q2] (m×3, orthonormal columns): y's
/// component off range(Q), plus h. Qᵀy in four-lane partial sums (a fixed order).
inline void projectOntoAffine(Index m, const double* __restrict y, const double* __restrict q0, const double* __restrict q1,
                              const double* __restrict q2, const double* __restrict h, double* __restrict out) {
  double p[3][4] = {};
  Index i = 0;
  for (; i + 4 <= m; i += 4)
    for (int l = 0; l < 4; ++l) {
      p[0][l] += y[i + l] * q0[i + l];
      p[1][l] += y[i + l] * q1[i + l];
      p[2][l] += y[i + l] * q2[i + l];
    }
  for (; i < m; ++i) {
    p[0][0] += y[i] * q0[i];
    p[1][0] += y[i] * q1[i];
    p[2][0] += y[i] * q2[i];
  }
  double c[3];
  for (int j = 0; j < 3; ++j) c[j] = (p[j][0] + p[j][1]) + (p[j][2] + p[j][3]);
  for (i = 0; i < m; ++i) out[i] = y[i] - (c[0] * q0[i] + c[1] * q1[i] + c[2] * q2[i]) + h[i];
}

// The iteration's three row kernels, one per interior vertex or triangle, each compiled for AVX2
// and the baseline (the helpers above are inlined into them).

/// Row v of step 2's varying right-hand side, Gᵀ A V1 + M V2: q = mass·v2 + Σ_a w_a·V1_{s_a} over
/// v's `count` incident (triangle, corner) pairs, w_a the corner's basis gradient times the
/// triangle's area (x with a row's x parts, y with its y parts); V1's rows are 2m values, `stride`
/// apart.
KC_VECTOR_CLONES void gatherRow(Index m, double mass, const double* __restrict v2, const std::pair<int, int>* adjacent,
                                const Vec2* weights, Index count, const double* V1, Index stride, double* __restrict q) {
  for (Index i = 0; i < m; ++i) q[i] = mass * v2[i];
  for (Index a = 0; a < count; ++a) {
    const double* __restrict v = V1 + Index(adjacent[a].first) * stride;
    const double wx = weights[a].x(), wy = weights[a].y();
    for (Index i = 0; i < m; ++i) q[i] += wx * v[i] + wy * v[m + i];
  }
}

/// Steps 3 and 1 at one interior vertex (m controls): from y, its row of the Y-system's solution,
/// Z's new row y (I − QQᵀ) + c, then U2 = V2 − Z, dz = Z's change (into u2 and dz when given),
/// z = Z (the window's average zavg, when given, moves toward it by `rate`), then the clamp and
/// the next V2. shares: |dz|², |W − Z|². `buffer`: 4m doubles.
KC_VECTOR_CLONES void vertexStep(Index m, double alpha, const double* y, const double* q0, const double* q1, const double* q2,
                                 const double* c, double* z, double* v2, double* u2, double* dz, double* zavg, double rate,
                                 double* buffer, double shares[2]) {
  double* znew = buffer;
  double* r = buffer + m;
  if (!u2) u2 = buffer + 2 * m;
  if (!dz) dz = buffer + 3 * m;
  projectOntoAffine(m, y, q0, q1, q2, c, znew);
  affineStep(m, znew, v2, z, u2, dz);
  if (zavg) moveToward(m, rate, z, zavg);
  clampRow(m, alpha, z, u2, v2, r);
  shares[0] = sumOfSquares(dz, m);
  shares[1] = sumOfSquares(r, m);
}

/// Steps 3 and 1 at one triangle (m controls): from the corner rows f0, f1, f2 of [Wb; Z] and the
/// corners' basis gradients gr, G = ∇_s, U1_s = V1_s − G (stored in u1 and the average u1avg
/// moved toward it by `rate`, each when given), X = shrink(G − U1_s, thresholds) and V1_s ← αX +
/// (1 − α)G + U1_s in v1. Returns |X − G|². `buffer`: 6m doubles.
KC_VECTOR_CLONES double triangleStep(Index m, double alpha, const std::array<Vec2, 3>& gr, const double* f0, const double* f1,
                                     const double* f2, const double* threshold, double* v1, double* u1, double* u1avg,
                                     double rate, double* buffer) {
  double* g = buffer;  // x parts, then y parts
  double* u = buffer + 2 * m;
  double* r = buffer + 4 * m;
  gradientOf(m, gr, f0, f1, f2, g, g + m);
  difference(2 * m, v1, g, u);
  if (u1) std::copy(u, u + 2 * m, u1);
  if (u1avg) moveToward(2 * m, rate, u, u1avg);
  shrinkRow(m, alpha, g, u, threshold, v1, r);
  return sumOfSquares(r, 2 * m);
}

/// Iterations from a certificate check at iteration k with relative gap `gap` to the next: a
/// geometric schedule, max(20, k/5), or sooner when the gap's fall since the previous check
/// (iteration `lastK`, gap `lastGap`; lastK = 0: none), taken as geometric, reaches `target`
/// earlier (with 10% to spare, at least 10 iterations: each check costs a few iterations' time).
int nextCheckIn(int k, double gap, int lastK, double lastGap, double target) {
  const int geometric = std::max(20, k / 5);
  if (lastK <= 0 || !(gap < lastGap) || !(gap > target)) return geometric;
  const double ratePerIteration = std::log(lastGap / gap) / double(k - lastK);
  const double predicted = 1.1 * std::log(gap / target) / ratePerIteration;
  return int(std::clamp(std::ceil(predicted), 10.0, double(geometric)));
}

/// Σ of per-row partial sums in a fixed order (bit-identical for any thread count).
double sum(const std::vector<double>& parts) {
  double s = 0.0;
  for (double p : parts) s += p;
  return s;
}

/// Runs the ADMM iterations on all threads or on the calling thread alone, whichever was measured
/// faster. Each iteration has a few parallel loops of a fraction of a millisecond; on a machine
/// shared with other work, every loop waits for all threads to be scheduled, which can make 2
/// threads several times slower than 1. Results do not depend on the choice (every loop writes
/// its own rows, sums are reduced in a fixed order), so it is made by timing: a probe runs
/// kWarm + kProbe iterations in parallel, then as many serially, and compares the two ways' median
/// times of their last kProbe iterations (the first ones after a switch wait for sleeping threads
/// or cold caches; the median ignores one iteration disturbed by other work); the faster way runs
/// until the next probe, kPeriod iterations later, twice as long (up to kMaxPeriod) each time the
/// answer repeats.
class ThreadChoice {
 public:
  explicit ThreadChoice(bool canParallel) : m_can(canParallel) {}
  /// Whether iteration k (1-based) runs in parallel.
  bool parallel(int k) const {
    if (!m_can) return false;
    const int offset = k - m_probeStart;
    if (offset >= 0 && offset < 2 * kPhase) return offset < kPhase;
    return m_parallelFaster;
  }
  /// Records the wall time of iteration k.
  void record(int k, double seconds) {
    const int offset = k - m_probeStart;
    if (offset < 0 || offset >= 2 * kPhase) return;
    if (offset % kPhase >= kWarm) m_time[offset / kPhase][offset % kPhase - kWarm] = seconds;
    if (offset < 2 * kPhase - 1) return;
    for (auto& t : m_time) std::nth_element(t.begin(), t.begin() + kProbe / 2, t.end());
    const bool faster = m_time[0][kProbe / 2] <= m_time[1][kProbe / 2];
    // The same answer again: probe half as often (the losing way can cost several iterations).
    m_period = m_probed && faster == m_parallelFaster ? std::min(2 * m_period, kMaxPeriod) : kPeriod;
    m_parallelFaster = faster;
    m_probed = true;
    m_probeStart += m_period;
  }

 private:
  static constexpr int kWarm = 1, kProbe = 3, kPhase = kWarm + kProbe, kPeriod = 100, kMaxPeriod = 800;
  bool m_can;
  bool m_parallelFaster = true, m_probed = false;
  int m_probeStart = 1, m_period = kPeriod;
  std::array<std::array<double, kProbe>, 2> m_time{};  // the probe's timed iterations: parallel, serial
};

}  // namespace

double lbcTau(LbcTau tau, double x) {
  x = std::clamp(x, 0.0, 1.0);
  switch (tau) {
    case LbcTau::Square: return x * x;
    case LbcTau::Constant: return 1.0;
    case LbcTau::Linear: return x;
    case LbcTau::Sqrt: return std::sqrt(x);
  }
  return 1.0;
}

struct LbcSolver::Impl {
  Index m = 0, r = 0, nb = 0, n = 0, nt = 0;  // controls, null-space dim, boundary, interior, triangles
  LbcTau tau = LbcTau::Square;              // of φ
  Points V;                                 // pixel positions (for the final QP)
  Triangles T;
  TriangleGradients g;                      // of the normalized mesh (diameter 1)
  double domainArea = 0.0;
  RowMatrix phi;                            // #T×m: φ_i^s = τ(D_i at the centroid of s)
  Weights Wb;                               // nb×m Dirichlet data
  Eigen::MatrixXd K;                        // m×3: [Ĉ 1] (normalized controls)
  Points Vn;                                // #V×2 normalized positions
  Eigen::Matrix<double, Eigen::Dynamic, 3> Q1;  // m×3 orthonormal basis of range(K): I − Q1 Q1ᵀ = MnᵀMn
  RowMatrix H;                              // n×m least-norm solution of H K = B (interior rows)
  RowMatrix C;  // n×m: H − P (L_II + M_II)⁻¹ (Gᵀ A ∇[Wb; H] + M_II H), step 2's constant part
  std::vector<Index> adjStart;              // interior vertex v → (triangle, corner) pairs
  std::vector<std::pair<int, int>> adj;
  std::vector<Vec2> adjWeight;              // per pair: the corner's basis gradient times the triangle's area
  SparseMatrix Lib;                         // n×nb block of the stiffness matrix
  detail::RowBlockCholesky system;          // L_II + M_II
  detail::RowBlockCholesky laplace;         // L_II (harmonic warm start)
  std::unique_ptr<detail::BarycentricLp> lp;  // the certificate's inner LP over the normalized controls
  std::vector<double> zeroRow;                // m zeros
  bool ok = true;
  double geodesicSeconds = 0.0, factorSeconds = 0.0;

  /// out = y (I − Q1 Q1ᵀ) + H_v = y MᵀM + H_v for interior vertex v and a row y (length m): the
  /// affine iterate's row from the Y-system's solution (H's rows lie in range(K), so y may
  /// include them).
  void projectRow(Index v, const double* y, double* out) const {
    projectOntoAffine(m, y, Q1.col(0).data(), Q1.col(1).data(), Q1.col(2).data(), &H(v, 0), out);
  }

  /// The m weights of (full) vertex v given the interior rows Z.
  const double* row(const RowMatrix& Z, int v) const { return v < nb ? &Wb(v, 0) : &Z(v - nb, 0); }

  /// Lower bound on the optimum of (15) by weak duality. With Λ = −μ a_s U1 (the multiplier of
  /// X = ∇W in the unweighted inner product) scaled per group into |Λ_s,i| ≤ φ_i^s a_s,
  ///   min_W F(∇W) ≥ ⟨Λ, E⟩ + Σ_v min_{w ≥ 0, wK = b_v} (GᵀΛ)_v · w,
  /// E = ∇ of the Dirichlet data; the inner minimum is a 3-constraint LP (BarycentricLp: the
  /// simplex method over triangles of controls containing v, a valid bound at every pivot).
  double dualBound(const RowMatrix& U1, double mu) const;

  /// The objective (15) of full weights W (#V×m), in the normalized mesh's units.
  double objective(const Weights& W) const;

  /// The iteration's start: harmonic coordinates (L_II W_I = −L_IB W_B) projected to the affine
  /// set when `harmonic`, else H (Y = 0). n×m interior rows.
  RowMatrix startingIterate(bool harmonic) const;

  /// Final weights from the affine iterate Z (interior rows): the Dirichlet rows, then Z, its
  /// rows with a negative entry replaced by the per-vertex QP's when `projectNonNegative` (thesis
  /// 4.1: the nearest w ≥ 0 with the same Cw = x, 1ᵀw = 1).
  struct FinalWeights {
    Weights W;
    Index projected = 0, failures = 0;  // rows the QP changed; rows where it was not optimal
    double maxProjection = 0.0;         // the largest change of a weight
  };
  FinalWeights finalWeights(const RowMatrix& Z, bool projectNonNegative) const;

  struct Admm;

  /// ∇_s of interior rows D (n×m; the boundary rows 0) into gx, gy (length m each).
  void interiorGradientRow(const RowMatrix& D, Index s, double* gx, double* gy) const {
    const auto& t = T[std::size_t(s)];
    auto rowOf = [&](int v) { return v < nb ? zeroRow.data() : &D(v - nb, 0); };
    gradientOf(m, g.gradient[std::size_t(s)], rowOf(t[0]), rowOf(t[1]), rowOf(t[2]), gx, gy);
  }

  /// ∇_s of the full weights [Wb; Z] into row s of G (#T×2m: x parts, then y parts).
  void gradientRow(const RowMatrix& Z, Index s, double* gx, double* gy) const {
    const auto& t = T[std::size_t(s)];
    gradientOf(m, g.gradient[std::size_t(s)], row(Z, t[0]), row(Z, t[1]), row(Z, t[2]), gx, gy);
  }
};

double LbcSolver::Impl::dualBound(const RowMatrix& U1, double mu) const {
  // Λ per triangle, clipped into the dual-feasible set of F.
  RowMatrix Lam(nt, 2 * m);
  std::vector<double> edgePart(std::size_t(nt), 0.0);
  parallelFor(nt, [&](Index s) {
    const auto& t = T[std::size_t(s)];
    const auto& gr = g.gradient[std::size_t(s)];
    const double a = g.area[std::size_t(s)];
    double e = 0.0;
    for (Index i = 0; i < m; ++i) {
      double lx = -mu * a * U1(s, i), ly = -mu * a * U1(s, m + i);
      const double len = std::sqrt(lx * lx + ly * ly), cap = phi(s, i) * a;
      if (len > cap) {
        lx *= cap / len;
        ly *= cap / len;
      }
      Lam(s, i) = lx;
      Lam(s, m + i) = ly;
      Vec2 boundaryGradient = Vec2::Zero();  // E_s,i: the Dirichlet vertices' part of ∇w_i
      for (int c = 0; c < 3; ++c)
        if (t[std::size_t(c)] < nb) boundaryGradient += gr[std::size_t(c)] * Wb(t[std::size_t(c)], i);
      e += lx * boundaryGradient.x() + ly * boundaryGradient.y();
    }
    edgePart[std::size_t(s)] = e;
  }, 256);
  // The inner LP per interior vertex, warm-started from the previous vertex's basis within fixed
  // runs of 16 vertices (the same runs whatever the thread count).
  std::vector<double> vertexPart(std::size_t(n), 0.0);
  constexpr Index kRun = 16;
  parallelForRange(n, kRun, [&](Index begin, Index end) {
    Eigen::VectorXd q(m);  // (GᵀΛ)_v
    for (Index run = begin; run < end; run += kRun) {
      std::array<int, 3> basis{-1, -1, -1};
      for (Index v = run; v < std::min(end, run + kRun); ++v) {
        q.setZero();
        for (Index a = adjStart[std::size_t(v)]; a < adjStart[std::size_t(v + 1)]; ++a) {
          const auto [s, c] = adj[std::size_t(a)];
          const Vec2& gr = g.gradient[std::size_t(s)][std::size_t(c)];
          for (Index i = 0; i < m; ++i) q(i) += gr.x() * Lam(s, i) + gr.y() * Lam(s, m + i);
        }
        vertexPart[std::size_t(v)] = lp->lowerBound(Vn.row(nb + v), q.data(), basis);
      }
    }
  });
  return sum(edgePart) + sum(vertexPart);
}

LbcSolver::LbcSolver(const CageMesh& mesh, LbcTau tau) : m_impl(std::make_unique<Impl>()) {
  Impl& d = *m_impl;
  d.tau = tau;
  d.m = mesh.controls;
  if (d.m < 3) throw std::invalid_argument("LBC: the cage needs at least 3 control points");
  if (mesh.status != SolveStatus::Ok || mesh.T.empty() || mesh.size() < d.m)
    throw std::invalid_argument("LBC: the cage mesh is empty (the mesher did not finish)");
  d.r = d.m - 3;
  d.nb = mesh.boundary;
  d.n = mesh.size() - mesh.boundary;
  d.nt = Index(mesh.T.size());
  d.V = mesh.V;
  d.T = mesh.T;

  // Normalized geometry: centred, bounding-box diameter 1 (the paper's scaling).
  const Vec2 lo = mesh.V.colwise().minCoeff(), hi = mesh.V.colwise().maxCoeff();
  const Vec2 center = 0.5 * (lo + hi);
  const double scale = (hi - lo).norm();
  d.Vn = (mesh.V.rowwise() - center.transpose()) / scale;
  const Points& Vn = d.Vn;
  d.g = triangleGradients(Vn, d.T);
  for (double a : d.g.area) d.domainArea += a;
  const SparseMatrix L = stiffnessMatrix(d.T, d.g, mesh.size());

  // φ from geodesic distances to the controls (heat method), normalized by their maxima.
  auto t0 = std::chrono::steady_clock::now();
  std::vector<Index> sources(static_cast<std::size_t>(d.m));
  for (Index i = 0; i < d.m; ++i) sources[std::size_t(i)] = i;
  HeatGeodesicReport heat;
  Eigen::MatrixXd D = heatGeodesics(Vn, d.T, d.g, L, sources, &heat);
  d.ok = heat.ok;
  for (Index i = 0; i < d.m; ++i) {
    const double mx = D.col(i).maxCoeff();
    if (mx > 0.0) D.col(i) /= mx;
  }
  d.phi.resize(d.nt, d.m);
  parallelFor(d.nt, [&](Index s) {
    const auto& t = d.T[std::size_t(s)];
    for (Index i = 0; i < d.m; ++i) d.phi(s, i) = lbcTau(tau, (D(t[0], i) + D(t[1], i) + D(t[2], i)) / 3.0);
  }, 256);
  d.geodesicSeconds = secondsSince(t0);

  // Dirichlet data (eq. 5): Lagrange at the controls, linear along the cage edges.
  d.Wb = Weights::Zero(d.nb, d.m);
  d.zeroRow.assign(std::size_t(d.m), 0.0);
  for (Index v = 0; v < d.nb; ++v) {
    if (v < d.m) {
      d.Wb(v, v) = 1.0;
    } else {
      d.Wb(v, mesh.edge(v, 0)) += 1.0 - mesh.t(v);
      d.Wb(v, mesh.edge(v, 1)) += mesh.t(v);
    }
  }

  // Null space of Kᵀ (K = [Ĉ 1], m×3) and the least-norm H (eq. 15–17), from a QR of K.
  d.K.resize(d.m, 3);
  d.K.leftCols(2) = Vn.topRows(d.m);
  d.K.col(2).setOnes();
  const Eigen::MatrixXd& K = d.K;
  const Eigen::MatrixXd Q = K.householderQr().householderQ();
  d.Q1 = Q.leftCols(3);
  d.lp = std::make_unique<detail::BarycentricLp>(Points(Vn.topRows(d.m)));
  const Eigen::MatrixXd Kpinv = (K.transpose() * K).ldlt().solve(K.transpose());  // 3×m
  d.H.resize(d.n, d.m);
  for (Index v = 0; v < d.n; ++v) {
    const Eigen::RowVector3d b(Vn(d.nb + v, 0), Vn(d.nb + v, 1), 1.0);
    d.H.row(v) = b * Kpinv;
  }

  // Interior vertex → incident (triangle, corner).
  d.adjStart.assign(std::size_t(d.n + 1), 0);
  for (const auto& t : d.T)
    for (int v : t)
      if (v >= d.nb) ++d.adjStart[std::size_t(v - d.nb + 1)];
  for (Index v = 0; v < d.n; ++v) d.adjStart[std::size_t(v + 1)] += d.adjStart[std::size_t(v)];
  d.adj.resize(std::size_t(d.adjStart[std::size_t(d.n)]));
  std::vector<Index> fill(d.adjStart.begin(), d.adjStart.end() - 1);
  for (std::size_t s = 0; s < d.T.size(); ++s)
    for (int c = 0; c < 3; ++c)
      if (d.T[s][std::size_t(c)] >= d.nb) d.adj[std::size_t(fill[std::size_t(d.T[s][std::size_t(c)] - d.nb)]++)] = {int(s), c};
  d.adjWeight.resize(d.adj.size());
  for (std::size_t a = 0; a < d.adj.size(); ++a) {
    const auto [s, c] = d.adj[a];
    d.adjWeight[a] = d.g.area[std::size_t(s)] * d.g.gradient[std::size_t(s)][std::size_t(c)];
  }

  // Factorizations: L_II + M_II (the Y-system, eq. B step 2) and L_II (harmonic warm start).
  t0 = std::chrono::steady_clock::now();
  if (d.n > 0) {
    SparseMatrix Lii = L.bottomRightCorner(d.n, d.n);
    d.Lib = L.block(d.nb, 0, d.n, d.nb);
    SparseMatrix S = Lii;
    for (Index v = 0; v < d.n; ++v) S.coeffRef(v, v) += d.g.vertexMass[std::size_t(d.nb + v)];
    d.ok = d.system.compute(S) && d.laplace.compute(Lii) && d.ok;
    // Step 2 is Z = P S⁻¹ (Gᵀ A (V1 − ∇[Wb; H]) + M_II (V2 − H)) + H, P = (I − Q1 Q1ᵀ) on the right,
    // S = L_II + M_II; its constant part, C = H − P S⁻¹ (L_IB Wb + L_II H + M_II H), is added per
    // row after the solve, so the loop reads neither H nor the constant right-hand side.
    RowMatrix constant = RowMatrix(d.Lib * d.Wb) + RowMatrix(Lii * d.H);
    for (Index v = 0; v < d.n; ++v) constant.row(v) += d.g.vertexMass[std::size_t(d.nb + v)] * d.H.row(v);
    d.C.resize(d.n, d.m);
    if (d.ok) {
      d.system.solveInPlace(constant);
      for (Index v = 0; v < d.n; ++v) {
        projectOntoAffine(d.m, &constant(v, 0), d.Q1.col(0).data(), d.Q1.col(1).data(), d.Q1.col(2).data(), d.zeroRow.data(),
                          &d.C(v, 0));
        d.C.row(v) = d.H.row(v) - d.C.row(v);
      }
    }
  }
  d.factorSeconds = secondsSince(t0);
}

LbcSolver::~LbcSolver() = default;

const Weights& LbcSolver::boundaryWeights() const { return m_impl->Wb; }

double LbcSolver::objective(const Weights& W) const { return m_impl->objective(W); }

double LbcSolver::Impl::objective(const Weights& W) const {
  if (W.rows() != nb + n || W.cols() != m) throw std::invalid_argument("LBC objective: W must be #V×m");
  std::vector<double> part(std::size_t(nt), 0.0);
  parallelFor(nt, [&](Index s) {
    const auto& t = T[std::size_t(s)];
    const auto& gr = g.gradient[std::size_t(s)];
    double e = 0.0;
    for (Index i = 0; i < m; ++i) {
      const Vec2 grad = gr[0] * W(t[0], i) + gr[1] * W(t[1], i) + gr[2] * W(t[2], i);
      e += phi(s, i) * grad.norm();
    }
    part[std::size_t(s)] = g.area[std::size_t(s)] * e;
  }, 256);
  return sum(part);
}

RowMatrix LbcSolver::Impl::startingIterate(bool harmonic) const {
  RowMatrix Z = H;
  if (harmonic && n > 0 && r > 0) {
    RowMatrix start = -(Lib * Wb);
    laplace.solveInPlace(start);
    parallelForRange(n, 64, [&](Index begin, Index end) {
      for (Index v = begin; v < end; ++v) projectRow(v, &start(v, 0), &Z(v, 0));
    });
  }
  return Z;
}

LbcSolver::Impl::FinalWeights LbcSolver::Impl::finalWeights(const RowMatrix& Z, bool projectNonNegative) const {
  FinalWeights out;
  Weights& W = out.W;
  W.resize(nb + n, m);
  W.topRows(nb) = Wb;
  W.bottomRows(n) = Z;
  if (!projectNonNegative || n == 0) return out;
  const ControlFrame frame(V.topRows(m));
  std::vector<unsigned char> changed(std::size_t(n), 0), failed(std::size_t(n), 0);
  std::vector<double> moved(std::size_t(n), 0.0);
  parallelFor(n, [&](Index v) {
    const Eigen::RowVectorXd target = Z.row(v);
    if (target.minCoeff() >= 0.0) return;
    const Vec2 x = V.row(nb + v);
    const SampleReport qp = sampleQp(frame, frame.normalize(x), std::span<const double>(target.data(), std::size_t(m)),
                                     std::span<double>(&W(nb + v, 0), std::size_t(m)));
    moved[std::size_t(v)] = (W.row(nb + v) - Z.row(v)).cwiseAbs().maxCoeff();
    changed[std::size_t(v)] = moved[std::size_t(v)] > 0.0;
    failed[std::size_t(v)] = qp.status != SolveStatus::Ok;
  }, 64);
  for (Index v = 0; v < n; ++v) {
    out.projected += changed[std::size_t(v)];
    out.failures += failed[std::size_t(v)];
    out.maxProjection = std::max(out.maxProjection, moved[std::size_t(v)]);
  }
  return out;
}

/// The ADMM iteration of (15) in Douglas–Rachford form. Its state is v = x̃ + U (per triangle
/// V1 = X̃ + U1, per vertex V2 = W̃ + U2): step 2 is the projection Z = P v onto the affine
/// iterates, U = v − B Z, then step 1 from B Z − U and the next v. Z is kept for the certificate;
/// U1, U2 (the certificate, a change of μ) and Z's last change (the dual residual) only when asked
/// (iterate's `keep`); the residuals' per-triangle and per-vertex shares are kept for the caller's
/// sums (the dual residual's per-triangle shares only when asked: dualShares). ∇Z is not stored: each pass
/// over the triangles computes it from Z's rows (one pass streams V1 and φ/μ only).
struct LbcSolver::Impl::Admm {
  const Impl& d;
  const double alpha;  // relaxation
  double mu;           // penalty
  RowMatrix Z, U1, U2, V1, V2, Qm, dZ;
  RowMatrix Zavg;       // Z averaged over iterations windowStart..k
  RowMatrix U1avg;      // U1 averaged over every kAverageStride-th iteration, iteration t weighted by t²
  int windowStart = 0;  // the iteration after the last check (0: none yet, Z is not averaged)
  std::vector<double> primalT, dualT, primalV, dualV;
  RowMatrix threshold;  // φ/μ (#T×m), the shrinkage's thresholds

  Admm(const Impl& solver, RowMatrix start, double relaxation, double penalty)
      : d(solver),
        alpha(relaxation),
        mu(penalty),
        Z(std::move(start)),
        U1(RowMatrix::Zero(d.nt, 2 * d.m)),
        U2(RowMatrix::Zero(d.n, d.m)),
        V1(d.nt, 2 * d.m),
        V2(d.n, d.m),
        Qm(d.n, d.m),
        dZ(d.n, d.m),
        Zavg(RowMatrix::Zero(d.n, d.m)),
        U1avg(RowMatrix::Zero(d.nt, 2 * d.m)),
        primalT(std::size_t(d.nt)),
        dualT(primalT),
        primalV(std::size_t(d.n)),
        dualV(primalV),
        threshold(d.phi / mu) {}

  /// U1's average takes every kAverageStride-th iteration (a pass over U1avg costs about a quarter
  /// of the triangle pass; U1 changes little from one iteration to the next).
  static constexpr int kAverageStride = 4;

  /// Step 1 of triangle s (eq. 30: X = shrink(G − U1, φ/μ)) from its gradient g = ∇_s[Wb; Z]
  /// and u = U1_s (x parts, then y parts), and its next V1 = αX + (1 − α)G + U1; returns
  /// a_s |X − G|² (the primal residual's share). `scratch`: 2m doubles.
  double shrink(Index s, const double* gs, const double* us, double* scratch) {
    shrinkRow(d.m, alpha, gs, us, &threshold(s, 0), &V1(s, 0), scratch);
    return d.g.area[std::size_t(s)] * sumOfSquares(scratch, 2 * d.m);
  }

  /// Step 1 of interior vertex v (eq. 31: W = max(0, Z − U2)) and its next V2; returns m_v |W − Z|².
  /// `scratch`: m doubles.
  double clamp(Index v, double* scratch) {
    clampRow(d.m, alpha, &Z(v, 0), &U2(v, 0), &V2(v, 0), scratch);
    return d.g.vertexMass[std::size_t(d.nb + v)] * sumOfSquares(scratch, d.m);
  }

  /// Step 1 everywhere (at the start, and after μ changed).
  void firstStep() {
    parallelForRange(d.nt, 256, [&](Index begin, Index end) {
      std::vector<double> g(std::size_t(4 * d.m));
      for (Index s = begin; s < end; ++s) {
        d.gradientRow(Z, s, g.data(), g.data() + d.m);
        primalT[std::size_t(s)] = shrink(s, g.data(), &U1(s, 0), g.data() + 2 * d.m);
      }
    });
    parallelForRange(d.n, 64, [&](Index begin, Index end) {
      std::vector<double> scratch(std::size_t(d.m));
      for (Index v = begin; v < end; ++v) primalV[std::size_t(v)] = clamp(v, scratch.data());
    });
  }

  /// Steps 2 and 3 of iteration k (1-based), then the next step 1; `parallel` or in one thread.
  /// U1, U2 and Z's change are stored only when `keep` (the certificate, the dual residual and a
  /// change of μ read them; the steps need only each row's, formed in the pass).
  void iterate(int k, bool parallel, bool keep) {
    const Index m = d.m, n = d.n, nt = d.nt;
    // The averages' steps: with j = k / kAverageStride, j² / Σ_{i ≤ j} i², so that iteration t
    // carries weight t² (U1), and 1/(iterations since the window's start) (Z).
    const bool averageU1 = k % kAverageStride == 0;
    const double j = double(k / kAverageStride), rate = 6.0 * j / ((j + 1.0) * (2.0 * j + 1.0));
    const bool averageZ = windowStart > 0;
    const double windowRate = averageZ ? 1.0 / double(k - windowStart + 1) : 0.0;
    auto grain = [&](Index count, Index g) { return parallel ? g : count; };
    // Step 2: the right-hand side's varying part Gᵀ A V1 + M V2 per interior vertex, gathered from
    // its triangles. With MᵀM = I − Q1 Q1ᵀ the Y-system's solution enters only as
    // (L_II + M_II)⁻¹ (right-hand side) MᵀM: solve for all m columns, then project each row and
    // add the constant part C.
    parallelForRange(n, grain(n, 64), [&](Index begin, Index end) {
      for (Index v = begin; v < end; ++v) {
        const Index a = d.adjStart[std::size_t(v)], count = d.adjStart[std::size_t(v + 1)] - a;
        gatherRow(m, d.g.vertexMass[std::size_t(d.nb + v)], &V2(v, 0), &d.adj[std::size_t(a)], &d.adjWeight[std::size_t(a)],
                  count, V1.data(), 2 * m, &Qm(v, 0));
      }
    });
    d.system.solveInPlace(Qm, parallel);
    // Step 3 and the next step 1 per interior vertex: Z, U2 = V2 − Z, then the clamp.
    parallelForRange(n, grain(n, 64), [&](Index begin, Index end) {
      std::vector<double> buffer(std::size_t(4 * m));
      double shares[2];
      for (Index v = begin; v < end; ++v) {
        vertexStep(m, alpha, &Qm(v, 0), d.Q1.col(0).data(), d.Q1.col(1).data(), d.Q1.col(2).data(), &d.C(v, 0), &Z(v, 0),
                   &V2(v, 0), keep ? &U2(v, 0) : nullptr, keep ? &dZ(v, 0) : nullptr, averageZ ? &Zavg(v, 0) : nullptr,
                   windowRate, buffer.data(), shares);
        const double mass = d.g.vertexMass[std::size_t(d.nb + v)];
        dualV[std::size_t(v)] = mass * shares[0];
        primalV[std::size_t(v)] = mass * shares[1];
      }
    });
    // ... and per triangle: G = ∇[Wb; Z], U1 = V1 − G, then the shrinkage.
    parallelForRange(nt, grain(nt, 256), [&](Index begin, Index end) {
      std::vector<double> buffer(std::size_t(6 * m));
      for (Index s = begin; s < end; ++s) {
        const auto& t = d.T[std::size_t(s)];
        const double share =
            triangleStep(m, alpha, d.g.gradient[std::size_t(s)], d.row(Z, t[0]), d.row(Z, t[1]), d.row(Z, t[2]), &threshold(s, 0),
                         &V1(s, 0), keep ? &U1(s, 0) : nullptr, averageU1 ? &U1avg(s, 0) : nullptr, rate, buffer.data());
        primalT[std::size_t(s)] = d.g.area[std::size_t(s)] * share;
      }
    });
  }

  /// The dual residual's per-triangle shares a_s |∇_s ΔZ|² of the last iteration (its per-vertex
  /// shares come with the iteration): a pass of its own, run only where the residual is read.
  void dualShares(bool parallel) {
    const Index m = d.m;
    parallelForRange(d.nt, parallel ? 256 : d.nt, [&](Index begin, Index end) {
      std::vector<double> dg(std::size_t(2 * m));
      for (Index s = begin; s < end; ++s) {
        d.interiorGradientRow(dZ, s, dg.data(), dg.data() + m);
        dualT[std::size_t(s)] = d.g.area[std::size_t(s)] * sumOfSquares(dg.data(), 2 * m);
      }
    });
  }

  /// Residual balancing: μ ← factor·μ, the scaled multipliers U = λ/μ follow, step 1 is redone.
  void scalePenalty(double factor) {
    mu *= factor;
    threshold = d.phi / mu;
    U1 /= factor;
    U1avg /= factor;  // the average of λ = μU1, in the new scale
    U2 /= factor;
    firstStep();
  }
};

LbcResult LbcSolver::solve(const LbcOptions& options) const {
  const Impl& d = *m_impl;
  if (options.tau != d.tau) throw std::invalid_argument("LBC: options.tau differs from the tau the solver's weights phi were built with");
  const auto start = std::chrono::steady_clock::now();
  LbcResult res;
  LbcReport& rep = res.report;
  rep.geodesicSeconds = d.geodesicSeconds;
  rep.factorSeconds = d.factorSeconds;
  if (!d.ok) {
    rep.status = SolveStatus::Singular;
    return res;
  }
  Impl::Admm admm(d, d.startingIterate(options.harmonicStart), options.relaxation, options.penalty);

  // Each call keeps in res.W (and the report) whichever has the lower objective: the final
  // weights of the iterate Z or the ones already there. The projected iterate's objective does
  // not fall monotonically (where Z dips below 0 varies over hundreds of iterations; on a
  // person-shaped cage the objective swings by several tenths of a percent between certificate
  // checks), and any non-negative barycentric candidate is as good an answer as its objective.
  auto finalize = [&](const RowMatrix& Z) {
    Impl::FinalWeights f = d.finalWeights(Z, options.projectNonNegative);
    const double value = d.objective(f.W);
    if (res.W.size() > 0 && !(value < rep.objective)) return;
    res.W = std::move(f.W);
    rep.objective = value;
    rep.projectedVertices = f.projected;
    rep.projectionFailures = f.failures;
    rep.maxProjection = f.maxProjection;
  };
  // The certificate at the present iterate: the best weights so far (the last iterate's and, once
  // a check has opened a window, the window's average) and the larger of the two lower bounds.
  auto certify = [&] {
    const auto tc = std::chrono::steady_clock::now();
    finalize(admm.Z);
    if (admm.windowStart > 0 && admm.windowStart <= rep.iterations) finalize(admm.Zavg);
    rep.lowerBound = d.dualBound(admm.U1, admm.mu);
    if (rep.iterations >= Impl::Admm::kAverageStride) rep.lowerBound = std::max(rep.lowerBound, d.dualBound(admm.U1avg, admm.mu));
    rep.certifySeconds += secondsSince(tc);
  };
  const auto iterStart = std::chrono::steady_clock::now();
  bool certified = false;  // rep.lowerBound and res.W are final
  if (d.n > 0 && d.r > 0) {
    const double norm = 1.0 / (double(d.m) * d.domainArea);
    int nextGapCheck = 0;
    double shown = 0.0;                                          // the progress reported
    double firstGap = std::numeric_limits<double>::quiet_NaN();  // at the first check
    double gapShown = 0.0;                                       // its way down to gapTolerance
    int lastCheck = 0;                                           // the previous check and its gap
    double lastGap = 0.0;
    rep.status = SolveStatus::NotConverged;
    admm.firstStep();
    ThreadChoice threads(threadCount() > 1);
    double lastPrimal = std::numeric_limits<double>::infinity();  // the previous iteration's
    for (int k = 1; k <= options.maxIterations; ++k) {
      const auto iterationStart = std::chrono::steady_clock::now();
      const bool parallel = threads.parallel(k);
      // Iterations that may stop (the previous one's primal residual passed, which the
      // iteration's fixed-point residual never raises; at most one iteration late), the last one
      // and residual balancing keep the multipliers and Z's change and compute the dual residual;
      // elsewhere it keeps the last value (the progress's).
      const bool mayStop =
          (lastPrimal <= options.tolerance && k >= nextGapCheck) || options.adaptivePenalty || k == options.maxIterations;
      admm.iterate(k, parallel, mayStop);
      rep.iterations = k;
      rep.primalResidual = lastPrimal = std::sqrt((sum(admm.primalT) + sum(admm.primalV)) * norm);
      if (mayStop) {
        admm.dualShares(parallel);
        rep.dualResidual = admm.mu * std::sqrt((sum(admm.dualT) + sum(admm.dualV)) * norm);
      }
      threads.record(k, secondsSince(iterationStart));
      if (mayStop && rep.primalResidual <= options.tolerance && rep.dualResidual <= options.tolerance && k >= nextGapCheck) {
        if (!(options.gapTolerance > 0.0)) {
          rep.status = SolveStatus::Ok;
          break;
        }
        // Certified stop: the returned weights' objective within gapTolerance of a lower bound.
        certify();
        const double gap = (rep.objective - rep.lowerBound) / std::abs(rep.lowerBound);
        if (std::isnan(firstGap)) firstGap = gap;
        gapShown = logProgress(gap, firstGap, options.gapTolerance);
        if (gap <= options.gapTolerance) {
          rep.status = SolveStatus::Ok;
          certified = true;
          break;
        }
        nextGapCheck = k + nextCheckIn(k, gap, lastCheck, lastGap, options.gapTolerance);
        lastCheck = k;
        admm.windowStart = k + 1;
        lastGap = gap;
      }
      if (options.progress && k % 10 == 0) {
        // The residuals' way down from 1 to the tolerance (with a gap to certify: the first 90% —
        // at the defaults the first check is usually the last —, then the gap's way from the first
        // check to gapTolerance), or the iteration share; never backwards (ADMM's residuals need
        // not fall at every iteration, nor the gap at every check).
        const double byResidual = logProgress(std::max(rep.primalResidual, rep.dualResidual), 1.0, options.tolerance);
        const double byStop = options.gapTolerance > 0.0 ? 0.9 * byResidual + 0.1 * gapShown : byResidual;
        shown = std::min(std::max({shown, byStop, double(k) / options.maxIterations}), 1.0);
        if (!options.progress(shown)) throw Cancelled();
      }
      if (options.adaptivePenalty) {  // residual balancing
        if (rep.primalResidual > 10.0 * rep.dualResidual) admm.scalePenalty(2.0);
        else if (rep.dualResidual > 10.0 * rep.primalResidual) admm.scalePenalty(0.5);
      }
    }
    rep.penalty = admm.mu;
  }
  rep.iterationSeconds = secondsSince(iterStart);

  if (!certified) {
    if (options.certify || options.gapTolerance > 0.0) certify();
    else finalize(admm.Z);
  }
  rep.seconds = secondsSince(start) + d.geodesicSeconds + d.factorSeconds;
  return res;
}

LbcResult solveLbc(const CageMesh& mesh, const LbcOptions& options) {
  return LbcSolver(mesh, options.tau).solve(options);
}

}  // namespace kc
