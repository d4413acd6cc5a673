#include "kc/sampling/inverse_mean_shift.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "kc/core/cage_edge_grid.h"
#include "kc/core/parallel.h"
#include "kc/core/spatial_grid.h"

namespace kc::sampling {
namespace {

/// The graded relaxation's bound on the largest move at convergence, in tolerances (see the loop).
constexpr double kGradedSlack = 3.0;
/// The fraction of free samples that must move less than the tolerance when a graded relaxation
/// stops (see the loop).
constexpr double kGradedSettled = 0.95;
/// The graded relaxation re-evaluates a sample's spacing once it is stale by up to this fraction:
/// after the sample moved kRelChange/g of its spacing (g the sizing's Lipschitz bound).
constexpr double kRelChange = 0.03;
/// The neighbour lists are rebuilt when a free sample has moved this fraction of its spacing, or
/// its spacing has grown by this fraction (at least g·kListMove), since they were built (see the loop).
constexpr double kListMove = 0.15;
constexpr double kListGrowth = 0.05;
/// How far (in the sample's spacings) a free sample's distance to the cage is measured when its
/// neighbour list is built (see the move's clearance test).
constexpr double kWallReach = 2.0;

/// X plus, for a periodic domain, copies of the samples near a side shifted by the period, so
/// that plain neighbour queries see the torus. ghostOf maps each row to its original sample.
void withGhosts(const Points& X, const Rect& domain, double radius, Points& Y, std::vector<Index>& ghostOf) {
  const Index n = X.rows();
  const double W = domain.width(), H = domain.height();
  std::vector<Vec2> extra;
  ghostOf.resize(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) ghostOf[static_cast<std::size_t>(i)] = i;
  for (Index i = 0; i < n; ++i) {
    const double x = X(i, 0), y = X(i, 1);
    const int sx = x - domain.x0 < radius ? 1 : (domain.x1 - x < radius ? -1 : 0);
    const int sy = y - domain.y0 < radius ? 1 : (domain.y1 - y < radius ? -1 : 0);
    auto add = [&](int ax, int ay) {
      extra.emplace_back(x + ax * W, y + ay * H);
      ghostOf.push_back(i);
    };
    if (sx != 0) add(sx, 0);
    if (sy != 0) add(0, sy);
    if (sx != 0 && sy != 0) add(sx, sy);
  }
  Y.resize(n + static_cast<Index>(extra.size()), 2);
  Y.topRows(n) = X;
  for (std::size_t k = 0; k < extra.size(); ++k) Y.row(n + static_cast<Index>(k)) = extra[k].transpose();
}

double wrap(double v, double lo, double period) {
  double t = std::fmod(v - lo, period);
  if (t < 0.0) t += period;
  return lo + t;
}

}  // namespace

InverseMeanShiftReport relaxInverseMeanShift(Points& X, Index firstFree, const RelaxRegion& region,
                                             const InverseMeanShiftOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double h = options.spacing;
  if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("inverse mean shift: spacing must be positive and finite");
  if (firstFree < 0 || firstFree > X.rows()) throw std::invalid_argument("inverse mean shift: firstFree out of range");
  if (region.periodic && !(region.domain.width() > 0.0 && region.domain.height() > 0.0))
    throw std::invalid_argument("inverse mean shift: periodic domain must have positive size");
  const double s = options.scale > 0.0 ? options.scale : 0.6 * h;
  const double lambda = options.step > 0.0 ? options.step : 0.3 * s * s;
  const double radius = std::max(options.cutoff, 0.5) * s;
  const double maxMove = options.maxMove * h, tolerance = options.tolerance * h, clearance = options.clearance * h;
  const double inv2s2 = 1.0 / (2.0 * s * s), gain = lambda / (s * s);
  // G_s shifted down by its value at the cut-off, so the force goes to zero continuously there:
  // with a jump, neighbours crossing the cut-off make samples chatter and the moves never settle.
  const double gCut = std::exp(-radius * radius * inv2s2);
  // G_s(d) − G_s(r) tabulated in u = d²/r² (linear interpolation, relative error ~1e-6): the
  // exponential is most of the cost of an iteration.
  constexpr int kTable = 2048;
  std::vector<double> table(kTable + 2);
  for (int q = 0; q <= kTable + 1; ++q)
    table[static_cast<std::size_t>(q)] = std::exp(-std::min(1.0, static_cast<double>(q) / kTable) * radius * radius * inv2s2) - gCut;
  const double invR2 = kTable / (radius * radius);
  auto shiftedGaussian = [&](double d2) {
    const double u = d2 * invR2;
    const int q = static_cast<int>(u);
    const double t = u - q;
    return (1.0 - t) * table[static_cast<std::size_t>(q)] + t * table[static_cast<std::size_t>(q) + 1];
  };

  // Graded: every sample's local spacing, as a multiple of h (1 where h(x) = hMax).
  const SizingField* sizing = options.sizing && options.sizing->graded() ? options.sizing : nullptr;
  std::vector<double> rel;
  Points relAt;  // where each rel was evaluated
  const double c = radius / h, g = sizing ? sizing->lipschitz() : 0.0;
  const double relStale = sizing ? kRelChange / g : 0.0;

  std::optional<CageEdgeGrid> locator;
  if (region.cage && region.cage->size() >= 2 && !region.periodic) locator.emplace(*region.cage, std::max(h, radius));

  const Index n = X.rows(), nFree = n - firstFree;
  InverseMeanShiftReport report;
  if (nFree == 0) {
    report.converged = true;
    return report;
  }
  Points next = X, Y;
  std::vector<Index> ghostOf;
  std::vector<double> moved(static_cast<std::size_t>(nFree));
  std::vector<unsigned char> rejected(static_cast<std::size_t>(nFree));
  SpatialGrid grid;
  double firstMove = 0.0, shown = 0.0;  // progress reporting

  // The domain's side is a plain wall: moves are projected onto it (inset by the clearance).
  // The cage is not convex: a move that would come closer than the clearance is refused.
  const Rect inner{region.domain.x0 + clearance, region.domain.y0 + clearance, region.domain.x1 - clearance,
                   region.domain.y1 - clearance};
  auto allowed = [&](const Vec2& from, const Vec2& to, double scale) {
    return region.periodic || !locator || locator->segmentClear(from, to, clearance * scale);
  };

  // Off the torus, each free sample keeps a neighbour list: the samples j within L·radius·h_kj/h
  // of it when the lists were built, L = listReach. A pair interacts while d < radius·h_kj/h; it
  // was listed if, since the build, neither sample moved more than kListMove of its spacing then
  // and no spacing grew by more than `growth`: d_then ≤ d + kListMove·(h_k + h_j) ≤
  // (c·(1 + growth) + 2·kListMove)·h_kj, c = radius/h, and L is that bound over c. A sample that
  // moves kListMove of its spacing changes it by up to g·kListMove: `growth` is at least that, so
  // on a steep gradation the lists are not rebuilt for growth long before they are for moves.
  const double growth = std::max(kListGrowth, g * kListMove);
  const double listReach = 1.0 + growth + 2.0 * kListMove / c, cl = listReach * c;
  // The list of sample k (relative spacing rk) holds the j within cl·sqrt((rk² + rj²)/2) of it, and
  // rj ≤ min(1, rk + g·d/h): the grid query's radius in units of h is the root of
  // d²(1 − cl²g²/2) − cl²g·rk·d − cl²rk² = 0, or cl·sqrt((rk² + 1)/2) where rj reaches 1 first.
  auto reach = [&](double rk) {
    const double a = 1.0 - cl * cl * g * g / 2.0, b = cl * cl * g * rk;
    const double bound = cl * std::sqrt(0.5 * (rk * rk + 1.0));
    if (a < 0.1) return bound;  // a steep gradation: the root grows without bound
    return std::min(bound, (b + std::sqrt(b * b + 4.0 * a * cl * cl * rk * rk)) / (2.0 * a));
  };
  const bool lists = !region.periodic;
  std::vector<std::vector<Index>> neighbours(lists ? static_cast<std::size_t>(nFree) : 0);
  Points listAt;                // positions when the lists were built
  std::vector<double> listRel;  // spacings when the lists were built (free samples, / h)
  std::vector<unsigned char> stale(static_cast<std::size_t>(nFree));
  // Off the torus, each free sample's distance to the cage where its list was built (up to
  // kWallReach of its spacing): a move whose segment stays farther from there than that distance
  // less the clearance (triangle inequality) is clear without querying the cage's edges.
  std::vector<double> wallAt(lists && locator ? static_cast<std::size_t>(nFree) : 0);
  if (!sizing) rel.assign(static_cast<std::size_t>(n), 1.0);  // uniform: h_k = h everywhere

  for (int it = 0; it < options.maxIterations; ++it) {
    if (sizing) {
      // h(x) is g-Lipschitz: re-evaluated only where a sample has moved more than kRelChange/g of
      // its spacing since, which changes h there by at most kRelChange (a larger jump kicks the
      // neighbours' pair bandwidths far past the tolerance and slows the settling).
      if (rel.empty()) {
        rel.resize(static_cast<std::size_t>(n));
        relAt = X;
        parallelFor(n, [&](Index i) { rel[static_cast<std::size_t>(i)] = (*sizing)(X.row(i)) / h; }, 256);
      } else {
        parallelFor(nFree, [&](Index f) {
          const Index i = firstFree + f;
          const std::size_t u = static_cast<std::size_t>(i);
          if ((X.row(i) - relAt.row(i)).squaredNorm() <= relStale * relStale * rel[u] * rel[u] * h * h) return;
          relAt.row(i) = X.row(i);
          rel[u] = (*sizing)(X.row(i)) / h;
        }, 256);
      }
    }
    if (region.periodic) {
      withGhosts(X, region.domain, radius, Y, ghostOf);
      grid.build(Y, 0.5 * radius);
    } else {
      bool rebuild = it == 0;
      if (!rebuild) {
        parallelFor(nFree, [&](Index f) {
          const Index k = firstFree + f;
          const double r0 = listRel[static_cast<std::size_t>(f)], limit = kListMove * r0 * h;
          stale[static_cast<std::size_t>(f)] =
              (X.row(k) - listAt.row(k)).squaredNorm() > limit * limit || rel[static_cast<std::size_t>(k)] > (1.0 + growth) * r0;
        }, 1024);
        rebuild = std::find(stale.begin(), stale.end(), 1) != stale.end();
      }
      if (rebuild) {
        grid.build(X, 0.5 * radius);
        listAt = X;
        listRel.assign(rel.begin() + firstFree, rel.end());
        parallelFor(nFree, [&](Index f) {
          const Index k = firstFree + f;
          const Vec2 xk = X.row(k);
          const double rk = rel[static_cast<std::size_t>(k)], limit2 = cl * cl * h * h;
          std::vector<Index>& list = neighbours[static_cast<std::size_t>(f)];
          if (!wallAt.empty()) wallAt[static_cast<std::size_t>(f)] = locator->distance(xk, kWallReach * rk * h);
          list.clear();
          grid.forEachWithin(xk, h * reach(rk), [&](Index j, double d2) {
            const double rj = rel[static_cast<std::size_t>(j)];
            if (j != k && d2 < limit2 * 0.5 * (rk * rk + rj * rj)) list.push_back(j);
          });
        }, 256);
      }
    }
    parallelFor(nFree, [&](Index f) {
      const Index k = firstFree + f;
      const Vec2 xk = X.row(k);
      const double rk = rel[static_cast<std::size_t>(k)];  // local spacing / h
      Vec2 force = Vec2::Zero();
      if (lists) {  // the pair's bandwidth s·h_kj/h, h_kj² = (h_k² + h_j²)/2
        const double rk2 = rk * rk;
        for (const Index j : neighbours[static_cast<std::size_t>(f)]) {
          const Vec2 d = xk - Vec2(X.row(j));
          const double rj = rel[static_cast<std::size_t>(j)];
          const double pair2 = 0.5 * (rk2 + rj * rj), d2 = d.squaredNorm();  // (h_kj / h)²
          if (d2 < radius * radius * pair2) force += d * shiftedGaussian(d2 / pair2);
        }
      } else {
        grid.forEachWithin(xk, radius, [&](Index j, double d2) {
          if (j == k) return;
          force += (xk - Vec2(Y.row(j))) * shiftedGaussian(d2);
        });
      }
      Vec2 step = gain * force;  // (6.4)
      const double len = step.norm();
      if (len > maxMove * rk) step *= maxMove * rk / len;
      Vec2 to = xk + step;
      if (!region.periodic) {
        const double inset = sizing ? clearance * (rk - 1.0) : 0.0;  // the walls' clearance at this sample's spacing
        to.x() = std::clamp(to.x(), std::min(inner.x0 + inset, xk.x()), std::max(inner.x1 - inset, xk.x()));
        to.y() = std::clamp(to.y(), std::min(inner.y0 + inset, xk.y()), std::max(inner.y1 - inset, xk.y()));
        step = to - xk;
      }
      unsigned char refused = 0;
      const bool farFromCage = !wallAt.empty() && wallAt[static_cast<std::size_t>(f)] - (xk - Vec2(listAt.row(k))).norm() -
                                                      step.norm() > clearance * rk * (1.0 + 1e-9);
      if (!farFromCage && !allowed(xk, to, rk)) {
        to = xk + 0.5 * step;  // one retry with half the step, then stay
        if (!allowed(xk, to, rk)) {
          to = xk;
          refused = 1;
        }
      }
      moved[static_cast<std::size_t>(f)] = (to - xk).norm() / rk;  // in units of the sample's own spacing
      if (region.periodic) {
        to.x() = wrap(to.x(), region.domain.x0, region.domain.width());
        to.y() = wrap(to.y(), region.domain.y0, region.domain.height());
      }
      next.row(k) = to.transpose();
      rejected[static_cast<std::size_t>(f)] = refused;
    }, 256);
    X.swap(next);  // fixed rows are equal in both; every free row of `next` is rewritten
    double largest = 0.0;
    for (Index f = 0; f < nFree; ++f) {
      largest = std::max(largest, moved[static_cast<std::size_t>(f)]);
      report.rejectedMoves += rejected[static_cast<std::size_t>(f)];
    }
    report.iterations = it + 1;
    report.lastMove = largest / h;
    report.largestMoves.push_back(report.lastMove);
    if (options.progress) {
      // The largest move shrinks roughly geometrically from the first iteration's to the
      // tolerance: log progress between them, never behind the iteration budget, never backwards.
      if (it == 0) firstMove = std::max(largest, tolerance);
      const double towards = logProgress(largest, firstMove, tolerance);
      shown = std::max({shown, static_cast<double>(it + 1) / options.maxIterations, std::min(towards, 0.99)});
      if (!options.progress(shown)) throw Cancelled();  // every iteration: a cancel is seen within one iteration
    }
    if (largest < tolerance) {
      report.converged = true;
      break;
    }
    // Graded: rows of samples in a corridor a few samples wide (a narrow gap) drift along it for
    // O(n²) iterations after everything else has settled; the graded relaxation stops when 95% of
    // the free samples move less than the tolerance and none more than kGradedSlack times it: the
    // drift no longer changes the sampling's separation or fill (in units of h(x)).
    if (sizing && largest < kGradedSlack * tolerance) {
      std::vector<double> sorted(moved);
      const auto q = sorted.begin() + static_cast<std::ptrdiff_t>(kGradedSettled * static_cast<double>(sorted.size() - 1));
      std::nth_element(sorted.begin(), q, sorted.end());
      if (*q < tolerance) {
        report.converged = true;
        break;
      }
    }
  }
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace kc::sampling
