#include "kc/core/exterior_weights.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "kc/core/parallel.h"
#include "kc/core/timing.h"
#include "sparse_cholesky.h"

namespace kc {
namespace detail {

/// Where a grid edge meets the cage: fraction t along the grid edge (from its lower-index end) and
/// the point's edge data: cage edge a→b at parameter s (λ_a = 1 − s, λ_b = s).
struct GridCrossing {
  double t = 0.0;
  int a = -1, b = -1;
  double s = 0.0;
};

}  // namespace detail

namespace {

using Clock = std::chrono::steady_clock;
using Crossing = detail::GridCrossing;

/// The crossings nearest to each end of one grid edge.
struct GridEdgeCuts {
  Crossing low{std::numeric_limits<double>::infinity()};    ///< Smallest t.
  Crossing high{-std::numeric_limits<double>::infinity()};  ///< Largest t.
  bool cut() const { return low.a >= 0; }
  void add(const Crossing& c) {
    if (c.t < low.t) low = c;
    if (c.t > high.t) high = c;
  }
};

/// Crossings of the cage with the lines of one grid direction. `lines` are the coordinates of
/// the lines (ys for rows), `along` the coordinates along them (xs for rows); axis 1 = rows
/// (y = const), axis 0 = columns (x = const). Uses insideCage's half-open rule, so that the
/// crossings along rows give the same even-odd classification.
struct LineCrossings {
  std::vector<GridEdgeCuts> cuts;            ///< (lines)×(along−1) grid edges, line-major.
  std::vector<std::vector<double>> at;       ///< Per line: positions of the crossings with loop edges (parity).

  /// onLoop: per edge, whether it bounds the interior (loopEdges); open sticks cut grid edges but
  /// do not count for the parity.
  LineCrossings(const std::vector<double>& lines, const std::vector<double>& along, const Cage& cage,
                const std::vector<std::array<int, 2>>& edges, const std::vector<char>& onLoop, int axis)
      : cuts(lines.size() * (along.size() - 1)), at(lines.size()) {
    const int other = 1 - axis;
    const std::size_t nAlong = along.size();
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const auto [a, b] = edges[e];
      const Vec2 A = cage.C.row(a), B = cage.C.row(b);
      const double lo = std::min(A(axis), B(axis)), hi = std::max(A(axis), B(axis));
      auto first = std::lower_bound(lines.begin(), lines.end(), lo);
      for (auto it = first; it != lines.end() && *it <= hi; ++it) {
        const double y = *it;
        if ((A(axis) > y) == (B(axis) > y)) continue;
        const double x = A(other) + (y - A(axis)) * (B(other) - A(other)) / (B(axis) - A(axis));
        const double s = (y - A(axis)) / (B(axis) - A(axis));
        const std::size_t line = std::size_t(it - lines.begin());
        if (onLoop[e]) at[line].push_back(x);
        if (x < along.front() || x > along.back()) continue;
        std::size_t k = std::size_t(std::upper_bound(along.begin(), along.end(), x) - along.begin()) - 1;
        k = std::min(k, nAlong - 2);
        const double t = (x - along[k]) / (along[k + 1] - along[k]);
        cuts[line * (nAlong - 1) + k].add({t, a, b, s});
        if (t == 0.0 && k > 0) cuts[line * (nAlong - 1) + k - 1].add({1.0, a, b, s});
      }
    }
  }
};

/// Edge data at the cage point closest to p (a fallback for rounding at vertices on the cage).
Crossing closestEdgeData(const Cage& cage, const std::vector<std::array<int, 2>>& edges, const Vec2& p,
                         double* distance = nullptr) {
  Crossing best;
  double bestDist = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : edges) {
    const Vec2 A = cage.C.row(a), d = Vec2(cage.C.row(b)) - A;
    const double s = std::clamp((p - A).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double dist = (A + s * d - p).norm();
    if (dist < bestDist) bestDist = dist, best = {0.0, a, b, s};
  }
  if (distance) *distance = bestDist;
  return best;
}

/// Whether p lies in the band of stick A–B: within r of the segment beside it, within capRadius
/// of its ends beyond them (the picture beyond a stick's end belongs to the background).
bool inStickBand(const Vec2& p, const Vec2& A, const Vec2& B, double r, double capRadius) {
  const Vec2 d = B - A;
  const double t = (p - A).dot(d) / d.squaredNorm();
  if (t < 0.0) return (p - A).norm() <= capRadius;
  if (t > 1.0) return (p - B).norm() <= capRadius;
  return (A + t * d - p).norm() <= r;
}

/// The grid vertices within a stick band: per open stick, the vertices of its capsule
/// (radius max(fraction · length, cells · cell diagonal)), found over the capsule's bounding box.
std::vector<std::uint8_t> stickBandVertices(const std::vector<double>& xs, const std::vector<double>& ys, const Cage& cage,
                                            const std::vector<std::array<int, 2>>& edges, const std::vector<char>& onLoop,
                                            const ExteriorWeightsOptions& options) {
  const int nx = int(xs.size()), ny = int(ys.size());
  std::vector<std::uint8_t> band(std::size_t(nx) * std::size_t(ny), 0);
  const double dx = xs[1] - xs[0], dy = ys[1] - ys[0];
  const double minRadius = options.stickBandCells * std::hypot(dx, dy);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (onLoop[e]) continue;
    const Vec2 A = cage.C.row(edges[e][0]), B = cage.C.row(edges[e][1]);
    const double r = std::max(options.stickBand * (B - A).norm(), minRadius);
    const auto first = [](const std::vector<double>& axis, double lo) {
      return int(std::lower_bound(axis.begin(), axis.end(), lo) - axis.begin());
    };
    const int i0 = first(xs, std::min(A.x(), B.x()) - r), i1 = first(xs, std::max(A.x(), B.x()) + r + 1e-9);
    const int j0 = first(ys, std::min(A.y(), B.y()) - r), j1 = first(ys, std::max(A.y(), B.y()) + r + 1e-9);
    for (int j = j0; j < std::min(j1, ny); ++j)
      for (int i = i0; i < std::min(i1, nx); ++i)
        if (inStickBand(Vec2(xs[std::size_t(i)], ys[std::size_t(j)]), A, B, r, minRadius)) band[std::size_t(j * nx + i)] = 1;
  }
  return band;
}

}  // namespace

/// The exterior's linear system A h = B_cage λ + B_band W_band, factorized once.
struct ExteriorSystem {
  Index m = 0;
  double keep = 0.0;                            ///< Entries with |h| ≤ keep are dropped (the anchor absorbs them).
  std::vector<int> id;                          ///< Grid vertex → unknown (−1: not solved for).
  std::vector<int> follow;                      ///< Grid vertex → followData index (−1: none).
  std::vector<Crossing> followData;             ///< Border vertices that follow the cage: edge data there.
  std::vector<Eigen::Triplet<double>> cageData; ///< (unknown, control, value), sorted by control.
  std::vector<Eigen::Triplet<double>> bandData; ///< (unknown, grid vertex in the band, coefficient).
  int unknowns = 0;
  bool ok = true;
  detail::SupernodalCholesky llt;
  mutable std::mutex solving;                   ///< CHOLMOD's workspace is per factorization.

  /// Solves for every control (in blocks of columns, so memory stays #U × block) with the band's
  /// data from W (null: 0 there) and writes H (#rows = exterior.size()) and the weight range.
  void fill(ExteriorWeights& out, const Weights* W) const {
    ExteriorWeightsReport& rep = out.report;
    const int nu = unknowns;
    std::vector<std::vector<std::pair<int, double>>> kept(static_cast<std::size_t>(nu));
    std::vector<double> rowMin(static_cast<std::size_t>(nu), 0.0), rowMax = rowMin, rowSum = rowMin;
    if (nu > 0 && ok && (bandData.empty() || W)) {
      std::lock_guard<std::mutex> lock(solving);
      const Index block = 32;
      auto next = cageData.begin();
      for (Index c0 = 0; c0 < m; c0 += block) {
        const Index nb = std::min(block, m - c0);
        Eigen::MatrixXd B = Eigen::MatrixXd::Zero(nu, nb);
        for (; next != cageData.end() && next->col() < c0 + nb; ++next) B(next->row(), next->col() - c0) += next->value();
        if (W)
          for (const auto& t : bandData) {  // the field's weights made non-negative: h stays in [0, 1]
            const auto w = W->row(t.col());
            const double mass = w.cwiseMax(0.0).sum();
            if (mass > 0.0) B.row(t.row()) += (t.value() / mass) * w.segment(c0, nb).cwiseMax(0.0);
          }
        const Eigen::MatrixXd X = llt.solve(B);
        parallelFor(nu, [&](Index u) {
          auto& row = kept[std::size_t(u)];
          for (Index c = 0; c < nb; ++c) {
            const double h = X(u, c);
            rowMin[std::size_t(u)] = std::min(rowMin[std::size_t(u)], h);
            rowMax[std::size_t(u)] = std::max(rowMax[std::size_t(u)], h);
            rowSum[std::size_t(u)] += h;
            if (std::abs(h) > keep) row.emplace_back(int(c0 + c), h);
          }
        }, 1024);
      }
    }
    if (nu > 0) {
      rep.minWeight = *std::min_element(rowMin.begin(), rowMin.end());
      rep.maxWeight = *std::max_element(rowMax.begin(), rowMax.end());
      rep.maxSum = *std::max_element(rowSum.begin(), rowSum.end());
    }

    // H: kept h_i and the anchor 1 − Σ kept h_i per exterior row.
    const Index nv = Index(out.exterior.size()), ng = Index(id.size());
    out.H = CompactWeights(nv, m + 1);
    int* outer = out.H.outerIndexPtr();
    outer[0] = 0;
    for (Index v = 0; v < nv; ++v) {
      const int u = v < ng ? id[std::size_t(v)] : -1;
      const bool followsCage = v < ng && follow[std::size_t(v)] >= 0;
      outer[v + 1] = outer[v] + (u >= 0 ? int(kept[std::size_t(u)].size()) + 1
                                        : (followsCage ? 2 : (out.exterior[std::size_t(v)] ? 1 : 0)));
    }
    out.H.resizeNonZeros(outer[nv]);
    parallelFor(nv, [&](Index v) {
      int k = outer[v];
      if (k == outer[v + 1]) return;
      if (const int f = follow[std::size_t(v)]; f >= 0) {  // λ at the closest cage point, no anchor
        const Crossing& c = followData[std::size_t(f)];
        const bool swap = c.b < c.a;  // column order within the row
        out.H.innerIndexPtr()[k] = swap ? c.b : c.a;
        out.H.valuePtr()[k] = swap ? c.s : 1.0 - c.s;
        out.H.innerIndexPtr()[k + 1] = swap ? c.a : c.b;
        out.H.valuePtr()[k + 1] = swap ? 1.0 - c.s : c.s;
        return;
      }
      double sum = 0.0;
      if (const int u = id[std::size_t(v)]; u >= 0)
        for (const auto& [c, h] : kept[std::size_t(u)]) {
          out.H.innerIndexPtr()[k] = c;
          out.H.valuePtr()[k++] = h;
          sum += h;
        }
      out.H.innerIndexPtr()[k] = int(m);
      out.H.valuePtr()[k] = 1.0 - sum;
    }, 1024);
  }
};

ExteriorWeights pinnedExteriorWeights(const std::vector<double>& xs, const std::vector<double>& ys, const Cage& cage,
                                      const ExteriorWeightsOptions& options) {
  auto t0 = Clock::now();
  const int nx = int(xs.size()), ny = int(ys.size());
  const Index nv = Index(nx) * ny, m = cage.size();
  const auto edges = cageEdges(cage);
  ExteriorWeights out;
  ExteriorWeightsReport& rep = out.report;
  auto system = std::make_shared<ExteriorSystem>();
  ExteriorSystem& sys = *system;
  sys.m = m;
  sys.keep = options.keepThreshold / double(std::max<Index>(m, 1));

  // Crossings along rows (y = ys[j]) and columns (x = xs[i]); even-odd interior along rows.
  const std::vector<char> onLoop = loopEdgeFlags(cage);
  const LineCrossings rows(ys, xs, cage, edges, onLoop, 1), cols(xs, ys, cage, edges, onLoop, 0);
  out.exterior.assign(std::size_t(nv), 1);
  if (hasInterior(cage))
    parallelFor(ny, [&](Index j) {
      std::vector<double> at = rows.at[std::size_t(j)];
      std::sort(at.begin(), at.end());
      std::size_t right = at.size();  // crossings with x > xs[i], counted from the right
      for (int i = nx - 1; i >= 0; --i) {
        while (right > 0 && at[right - 1] > xs[std::size_t(i)]) --right;
        out.exterior[std::size_t(j * nx + i)] = ((at.size() - right) % 2 == 1) ? 0 : 1;
      }
    }, 8);
  const bool sticks = std::find(onLoop.begin(), onLoop.end(), 0) != onLoop.end();
  if (options.stickBand > 0.0 && sticks) {
    out.band = stickBandVertices(xs, ys, cage, edges, onLoop, options);
    for (Index v = 0; v < nv; ++v)
      if (out.band[std::size_t(v)] && out.exterior[std::size_t(v)]) out.exterior[std::size_t(v)] = 0, ++rep.band;
      else out.band[std::size_t(v)] = 0;  // inside a loop already
  }

  // Unknowns: exterior vertices off the image border.
  // Border vertices closer than followDistance to the cage take the cage's data there instead.
  std::vector<int>& id = sys.id;
  std::vector<int>& follow = sys.follow;
  id.assign(std::size_t(nv), -1);
  follow.assign(std::size_t(nv), -1);
  int nu = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t v = std::size_t(j * nx + i);
      if (!out.exterior[v]) {
        ++rep.interior;
      } else if (i == 0 || j == 0 || i == nx - 1 || j == ny - 1) {
        double d = 0.0;
        const Crossing c = closestEdgeData(cage, edges, Vec2(xs[std::size_t(i)], ys[std::size_t(j)]), &d);
        if (d < options.followDistance) {
          follow[v] = int(sys.followData.size());
          sys.followData.push_back(c);
          ++rep.following;
        } else {
          ++rep.anchored;
        }
      } else {
        id[v] = nu++;
      }
    }
  rep.unknowns = sys.unknowns = nu;

  // Cotangent weights of the right-triangle grid: dy/dx on horizontal edges, dx/dy on vertical.
  const double dx = xs[1] - xs[0], dy = ys[1] - ys[0];
  const double cx = dy / dx, cy = dx / dy;
  std::vector<Eigen::Triplet<double>> aTrip;
  std::vector<Eigen::Triplet<double>>& bTrip = sys.cageData;
  aTrip.reserve(std::size_t(nu) * 5);
  const auto cutTerm = [&](int u, double c, const Crossing& x, double theta, double& diag) {
    const double w = c / std::max(theta, options.minCutFraction);
    diag += w;
    bTrip.emplace_back(u, x.a, w * (1.0 - x.s));
    bTrip.emplace_back(u, x.b, w * x.s);
    ++rep.cutEdges;
  };
  for (int j = 1; j + 1 < ny; ++j)
    for (int i = 1; i + 1 < nx; ++i) {
      const int u = id[std::size_t(j * nx + i)];
      if (u < 0) continue;
      double diag = 0.0;
      // (neighbour i, j, coefficient, cuts of the grid edge, true when this vertex is its low end)
      const GridEdgeCuts* hc = &rows.cuts[std::size_t(j * (nx - 1))];
      const GridEdgeCuts* vc = &cols.cuts[std::size_t(i * (ny - 1))];
      const struct {
        int ni, nj;
        double c;
        const GridEdgeCuts& g;
        bool low;
      } nb[4] = {{i + 1, j, cx, hc[i], true}, {i - 1, j, cx, hc[i - 1], false},
                 {i, j + 1, cy, vc[j], true}, {i, j - 1, cy, vc[j - 1], false}};
      for (const auto& n : nb) {
        const std::size_t nvtx = std::size_t(n.nj * nx + n.ni);
        if (n.g.cut()) {
          if (n.low) cutTerm(u, n.c, n.g.low, n.g.low.t, diag);
          else cutTerm(u, n.c, n.g.high, 1.0 - n.g.high.t, diag);
        } else if (id[nvtx] >= 0) {
          diag += n.c;
          aTrip.emplace_back(u, id[nvtx], -n.c);
        } else if (!out.band.empty() && out.band[nvtx]) {
          diag += n.c;  // the band's edge: the field's weights there (setFieldData)
          sys.bandData.emplace_back(u, int(nvtx), n.c);
        } else if (follow[nvtx] >= 0) {
          cutTerm(u, n.c, sys.followData[std::size_t(follow[nvtx])], 1.0, diag);  // a border vertex that follows the cage
        } else if (out.exterior[nvtx]) {
          diag += n.c;  // the pinned border: h = 0
        } else {
          ++rep.fallbackEdges;
          cutTerm(u, n.c, closestEdgeData(cage, edges, Vec2(xs[std::size_t(n.ni)], ys[std::size_t(n.nj)])), 1.0, diag);
        }
      }
      aTrip.emplace_back(u, u, diag);
    }
  SparseMatrix A(nu, nu);
  A.setFromTriplets(aTrip.begin(), aTrip.end());
  std::sort(bTrip.begin(), bTrip.end(), [](const auto& p, const auto& q) { return p.col() < q.col(); });
  rep.assembleSeconds = secondsSince(t0);

  // One factorization, m right-hand sides (setFieldData solves again with the band's data).
  t0 = Clock::now();
  if (nu > 0) {
    sys.llt.compute(A);
    sys.ok = sys.llt.info() == Eigen::Success;
  }
  rep.ok = sys.ok;
  rep.factorSeconds = secondsSince(t0);
  t0 = Clock::now();
  sys.fill(out, nullptr);
  rep.solveSeconds = secondsSince(t0);
  if (!sys.bandData.empty()) out.system = std::move(system);
  return out;
}

void setFieldData(ExteriorWeights& ext, const Weights& W) {
  if (!ext.system) return;
  const ExteriorSystem& sys = *ext.system;
  if (W.rows() < Index(sys.id.size()) || W.cols() != sys.m)
    throw std::invalid_argument("exterior weights: field weights are " + std::to_string(W.rows()) + "x" +
                                std::to_string(W.cols()) + ", need at least " + std::to_string(sys.id.size()) + "x" +
                                std::to_string(sys.m));
  const auto t0 = Clock::now();
  sys.fill(ext, &W);
  ext.report.solveSeconds = secondsSince(t0);
}

}  // namespace kc
