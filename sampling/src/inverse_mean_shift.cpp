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

/// G_s(d) − G_s(r): the Gaussian of (6.4) shifted down by its value at the cut-off r, so the force
/// goes to zero continuously there (with a jump, neighbours crossing the cut-off make samples
/// chatter and the moves never settle). Tabulated in u = d²/r² (linear interpolation, relative
/// error ~1e-6): the exponential is most of the cost of an iteration.
class ShiftedGaussian {
 public:
  ShiftedGaussian(double radius, double inv2s2) : table_(kTable + 2), invR2_(kTable / (radius * radius)) {
    const double gCut = std::exp(-radius * radius * inv2s2);
    for (int q = 0; q <= kTable + 1; ++q)
      table_[static_cast<std::size_t>(q)] =
          std::exp(-std::min(1.0, static_cast<double>(q) / kTable) * radius * radius * inv2s2) - gCut;
  }
  /// The value at squared distance d2 (< r²).
  double operator()(double d2) const {
    const double u = d2 * invR2_;
    const int q = static_cast<int>(u);
    const double t = u - q;
    return (1.0 - t) * table_[static_cast<std::size_t>(q)] + t * table_[static_cast<std::size_t>(q) + 1];
  }

 private:
  static constexpr int kTable = 2048;
  std::vector<double> table_;
  double invR2_;
};

/// One relaxation (relaxInverseMeanShift): the force's constants, the samples' local spacings,
/// the neighbour lists and the moves of the current iteration.
class Relaxation {
 public:
  Relaxation(Points& X, Index firstFree, const RelaxRegion& region, const InverseMeanShiftOptions& options)
      : X_(X),
        region_(region),
        h_(options.spacing),
        s_(options.scale > 0.0 ? options.scale : 0.6 * h_),
        radius_(std::max(options.cutoff, 0.5) * s_),
        maxMove_(options.maxMove * h_),
        clearance_(options.clearance * h_),
        gain_((options.step > 0.0 ? options.step : 0.3 * s_ * s_) / (s_ * s_)),
        shifted_(radius_, 1.0 / (2.0 * s_ * s_)),
        sizing_(options.sizing && options.sizing->graded() ? options.sizing : nullptr),
        n_(X.rows()),
        firstFree_(firstFree),
        nFree_(n_ - firstFree),
        lists_(!region.periodic),
        next_(X),
        moved_(static_cast<std::size_t>(nFree_)),
        rejected_(static_cast<std::size_t>(nFree_)),
        stale_(static_cast<std::size_t>(nFree_)) {
    const double c = radius_ / h_;
    g_ = sizing_ ? sizing_->lipschitz() : 0.0;
    relStale_ = sizing_ ? kRelChange / g_ : 0.0;
    if (region.cage && region.cage->size() >= 2 && !region.periodic) locator_.emplace(*region.cage, std::max(h_, radius_));
    // The domain's side is a plain wall: moves are projected onto it (inset by the clearance).
    inner_ = {region.domain.x0 + clearance_, region.domain.y0 + clearance_, region.domain.x1 - clearance_,
              region.domain.y1 - clearance_};
    // Off the torus, each free sample keeps a neighbour list: the samples j within L·radius·h_kj/h
    // of it when the lists were built, L = listReach. A pair interacts while d < radius·h_kj/h; it
    // was listed if, since the build, neither sample moved more than kListMove of its spacing then
    // and no spacing grew by more than `growth`: d_then ≤ d + kListMove·(h_k + h_j) ≤
    // (c·(1 + growth) + 2·kListMove)·h_kj, c = radius/h, and L is that bound over c. A sample that
    // moves kListMove of its spacing changes it by up to g·kListMove: `growth` is at least that, so
    // on a steep gradation the lists are not rebuilt for growth long before they are for moves.
    growth_ = std::max(kListGrowth, g_ * kListMove);
    const double listReach = 1.0 + growth_ + 2.0 * kListMove / c;
    cl_ = listReach * c;
    if (lists_) neighbours_.resize(static_cast<std::size_t>(nFree_));
    // Off the torus, each free sample's distance to the cage where its list was built (up to
    // kWallReach of its spacing): a move whose segment stays farther from there than that distance
    // less the clearance (triangle inequality) is clear without querying the cage's edges.
    if (lists_ && locator_) wallAt_.resize(static_cast<std::size_t>(nFree_));
    if (!sizing_) rel_.assign(static_cast<std::size_t>(n_), 1.0);  // uniform: h_k = h everywhere
  }

  /// One iteration of (6.4): every free sample moved at once. Returns the largest move in units of
  /// the moved sample's own spacing; counts the refused moves into `rejectedMoves`.
  double iterate(int it, Index& rejectedMoves) {
    if (sizing_) updateSpacings();
    if (region_.periodic) {
      withGhosts(X_, region_.domain, radius_, Y_, ghostOf_);
      grid_.build(Y_, 0.5 * radius_);
    } else if (it == 0 || listsStale()) {
      buildLists();
    }
    parallelFor(
        nFree_, [&](Index f) { move(f); }, 256);
    X_.swap(next_);  // fixed rows are equal in both; every free row of `next_` is rewritten
    double largest = 0.0;
    for (Index f = 0; f < nFree_; ++f) {
      largest = std::max(largest, moved_[static_cast<std::size_t>(f)]);
      rejectedMoves += rejected_[static_cast<std::size_t>(f)];
    }
    return largest;
  }

  /// Graded: whether kGradedSettled of the free samples moved less than `tolerance` in the last
  /// iteration (in units of their spacing).
  bool mostlySettled(double tolerance) const {
    std::vector<double> sorted(moved_);
    const auto q = sorted.begin() + static_cast<std::ptrdiff_t>(kGradedSettled * static_cast<double>(sorted.size() - 1));
    std::nth_element(sorted.begin(), q, sorted.end());
    return *q < tolerance;
  }

  bool graded() const { return sizing_ != nullptr; }

 private:
  /// Every sample's local spacing as a multiple of h (1 where h(x) = hMax). h(x) is g-Lipschitz:
  /// re-evaluated only where a sample has moved more than kRelChange/g of its spacing since, which
  /// changes h there by at most kRelChange (a larger jump kicks the neighbours' pair bandwidths far
  /// past the tolerance and slows the settling).
  void updateSpacings() {
    if (rel_.empty()) {
      rel_.resize(static_cast<std::size_t>(n_));
      relAt_ = X_;
      parallelFor(
          n_, [&](Index i) { rel_[static_cast<std::size_t>(i)] = (*sizing_)(X_.row(i)) / h_; }, 256);
      return;
    }
    parallelFor(
        nFree_,
        [&](Index f) {
          const Index i = firstFree_ + f;
          const std::size_t u = static_cast<std::size_t>(i);
          if ((X_.row(i) - relAt_.row(i)).squaredNorm() <= relStale_ * relStale_ * rel_[u] * rel_[u] * h_ * h_) return;
          relAt_.row(i) = X_.row(i);
          rel_[u] = (*sizing_)(X_.row(i)) / h_;
        },
        256);
  }

  /// Whether a free sample moved kListMove of its spacing, or its spacing grew by `growth`, since
  /// the lists were built.
  bool listsStale() {
    parallelFor(
        nFree_,
        [&](Index f) {
          const Index k = firstFree_ + f;
          const double r0 = listRel_[static_cast<std::size_t>(f)], limit = kListMove * r0 * h_;
          stale_[static_cast<std::size_t>(f)] = (X_.row(k) - listAt_.row(k)).squaredNorm() > limit * limit ||
                                                rel_[static_cast<std::size_t>(k)] > (1.0 + growth_) * r0;
        },
        1024);
    return std::find(stale_.begin(), stale_.end(), 1) != stale_.end();
  }

  /// The grid query's radius (units of h) of sample k's list at relative spacing rk: its list holds
  /// the j within cl·sqrt((rk² + rj²)/2) of it, and rj ≤ min(1, rk + g·d/h): the root of
  /// d²(1 − cl²g²/2) − cl²g·rk·d − cl²rk² = 0, or cl·sqrt((rk² + 1)/2) where rj reaches 1 first.
  double reach(double rk) const {
    const double a = 1.0 - cl_ * cl_ * g_ * g_ / 2.0, b = cl_ * cl_ * g_ * rk;
    const double bound = cl_ * std::sqrt(0.5 * (rk * rk + 1.0));
    if (a < 0.1) return bound;  // a steep gradation: the root grows without bound
    return std::min(bound, (b + std::sqrt(b * b + 4.0 * a * cl_ * cl_ * rk * rk)) / (2.0 * a));
  }

  void buildLists() {
    grid_.build(X_, 0.5 * radius_);
    listAt_ = X_;
    listRel_.assign(rel_.begin() + firstFree_, rel_.end());
    parallelFor(
        nFree_,
        [&](Index f) {
          const Index k = firstFree_ + f;
          const Vec2 xk = X_.row(k);
          const double rk = rel_[static_cast<std::size_t>(k)], limit2 = cl_ * cl_ * h_ * h_;
          std::vector<Index>& list = neighbours_[static_cast<std::size_t>(f)];
          if (!wallAt_.empty()) wallAt_[static_cast<std::size_t>(f)] = locator_->distance(xk, kWallReach * rk * h_);
          list.clear();
          grid_.forEachWithin(xk, h_ * reach(rk), [&](Index j, double d2) {
            const double rj = rel_[static_cast<std::size_t>(j)];
            if (j != k && d2 < limit2 * 0.5 * (rk * rk + rj * rj)) list.push_back(j);
          });
        },
        256);
  }

  /// The cage is not convex: a move that would come closer than the clearance is refused.
  bool allowed(const Vec2& from, const Vec2& to, double scale) const {
    return region_.periodic || !locator_ || locator_->segmentClear(from, to, clearance_ * scale);
  }

  /// Free sample f's move: next_, moved_ and rejected_ at f.
  void move(Index f) {
    const Index k = firstFree_ + f;
    const Vec2 xk = X_.row(k);
    const double rk = rel_[static_cast<std::size_t>(k)];  // local spacing / h
    Vec2 force = Vec2::Zero();
    if (lists_) {  // the pair's bandwidth s·h_kj/h, h_kj² = (h_k² + h_j²)/2
      const double rk2 = rk * rk;
      for (const Index j : neighbours_[static_cast<std::size_t>(f)]) {
        const Vec2 d = xk - Vec2(X_.row(j));
        const double rj = rel_[static_cast<std::size_t>(j)];
        const double pair2 = 0.5 * (rk2 + rj * rj), d2 = d.squaredNorm();  // (h_kj / h)²
        if (d2 < radius_ * radius_ * pair2) force += d * shifted_(d2 / pair2);
      }
    } else {
      grid_.forEachWithin(xk, radius_, [&](Index j, double d2) {
        if (j == k) return;
        force += (xk - Vec2(Y_.row(j))) * shifted_(d2);
      });
    }
    Vec2 step = gain_ * force;  // (6.4)
    const double len = step.norm();
    if (len > maxMove_ * rk) step *= maxMove_ * rk / len;
    Vec2 to = xk + step;
    if (!region_.periodic) {
      const double inset = sizing_ ? clearance_ * (rk - 1.0) : 0.0;  // the walls' clearance at this sample's spacing
      to.x() = std::clamp(to.x(), std::min(inner_.x0 + inset, xk.x()), std::max(inner_.x1 - inset, xk.x()));
      to.y() = std::clamp(to.y(), std::min(inner_.y0 + inset, xk.y()), std::max(inner_.y1 - inset, xk.y()));
      step = to - xk;
    }
    unsigned char refused = 0;
    const bool farFromCage =
        !wallAt_.empty() &&
        wallAt_[static_cast<std::size_t>(f)] - (xk - Vec2(listAt_.row(k))).norm() - step.norm() > clearance_ * rk * (1.0 + 1e-9);
    if (!farFromCage && !allowed(xk, to, rk)) {
      to = xk + 0.5 * step;  // one retry with half the step, then stay
      if (!allowed(xk, to, rk)) {
        to = xk;
        refused = 1;
      }
    }
    moved_[static_cast<std::size_t>(f)] = (to - xk).norm() / rk;  // in units of the sample's own spacing
    if (region_.periodic) {
      to.x() = wrap(to.x(), region_.domain.x0, region_.domain.width());
      to.y() = wrap(to.y(), region_.domain.y0, region_.domain.height());
    }
    next_.row(k) = to.transpose();
    rejected_[static_cast<std::size_t>(f)] = refused;
  }

  Points& X_;
  const RelaxRegion& region_;
  const double h_, s_, radius_, maxMove_, clearance_, gain_;
  const ShiftedGaussian shifted_;
  const SizingField* sizing_;
  const Index n_, firstFree_, nFree_;
  const bool lists_;  // neighbour lists (off the torus) or grid queries over the ghosts (on it)
  double g_ = 0.0, relStale_ = 0.0, growth_ = 0.0, cl_ = 0.0;
  Rect inner_;
  std::optional<CageEdgeGrid> locator_;
  std::vector<double> rel_;  // each sample's local spacing / h (graded: where relAt_ holds)
  Points relAt_, next_, Y_, listAt_;
  std::vector<Index> ghostOf_;
  std::vector<double> moved_;
  std::vector<unsigned char> rejected_, stale_;
  SpatialGrid grid_;
  std::vector<std::vector<Index>> neighbours_;
  std::vector<double> listRel_;  // spacings when the lists were built (free samples, / h)
  std::vector<double> wallAt_;
};

}  // namespace

InverseMeanShiftReport relaxInverseMeanShift(Points& X, Index firstFree, const RelaxRegion& region,
                                             const InverseMeanShiftOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double h = options.spacing;
  if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("inverse mean shift: spacing must be positive and finite");
  if (firstFree < 0 || firstFree > X.rows()) throw std::invalid_argument("inverse mean shift: firstFree out of range");
  if (region.periodic && !(region.domain.width() > 0.0 && region.domain.height() > 0.0))
    throw std::invalid_argument("inverse mean shift: periodic domain must have positive size");
  InverseMeanShiftReport report;
  if (X.rows() == firstFree) {
    report.converged = true;
    return report;
  }
  const double tolerance = options.tolerance * h;
  Relaxation relaxation(X, firstFree, region, options);
  double firstMove = 0.0, shown = 0.0;  // progress reporting
  for (int it = 0; it < options.maxIterations; ++it) {
    const double largest = relaxation.iterate(it, report.rejectedMoves);
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
    if (relaxation.graded() && largest < kGradedSlack * tolerance && relaxation.mostlySettled(tolerance)) {
      report.converged = true;
      break;
    }
  }
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace kc::sampling
