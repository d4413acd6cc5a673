// The exterior samples' weights continued from the inside (exterior_continuation.h).
#include "kc/core/weights/exterior_continuation.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "kc/core/cage_edge_grid.h"
#include "kc/core/parallel.h"
#include "kc/core/spatial_grid.h"

namespace kc {
namespace {
/// Seen from x, nearest points of two walls less than 60° apart lie on one side of it: the walls
/// of an outside wedge opening wider than 120° (cos 60° = 0.5), which is no gap.
constexpr double kOneSideCosine = 0.5;
/// In the two-sided blend of a refined gap, the fraction of the gap's width next to each wall
/// that continues that wall alone (see the header).
constexpr double kGapWall = 0.2;
/// The least turn towards the outside (radians, 60°) of the cage between two walls of a gap.
constexpr double kPocketTurn = 1.0471975511965976;

/// Turning of a closed polygon: prefix[k] = Σ_{v < k} τ_v, τ_v the turn at vertex v (radians,
/// positive towards the inside: a convex vertex), prefix[m] = 2π. Empty for a cage that is not
/// one closed polygon i → i+1 (mod m) (an edge graph: the pocket test is not made there).
std::vector<double> polygonTurning(const Cage& cage) {
  if (!isClosedPolygon(cage)) return {};
  const int m = static_cast<int>(cage.size());
  const double orientation = signedArea(cage.C) > 0.0 ? 1.0 : -1.0;
  std::vector<double> prefix(static_cast<std::size_t>(m) + 1, 0.0);
  for (int v = 0; v < m; ++v) {
    const Vec2 d1 = (cage.C.row(v) - cage.C.row((v + m - 1) % m)).transpose();
    const Vec2 d2 = (cage.C.row((v + 1) % m) - cage.C.row(v)).transpose();
    const double turn = std::atan2(d1.x() * d2.y() - d1.y() * d2.x(), d1.dot(d2));
    prefix[static_cast<std::size_t>(v) + 1] = prefix[static_cast<std::size_t>(v)] + orientation * turn;
  }
  return prefix;
}

/// True when edges a and b (of the polygon `turning` describes) bound a pocket of the outside: the
/// way along the cage from one to the other that turns least towards the inside turns towards
/// the outside by kPocketTurn or more. Always true without turning data.
bool boundsPocket(const std::vector<double>& turning, int a, int b) {
  if (turning.empty()) return true;
  const std::size_t m = turning.size() - 1;
  const auto ua = static_cast<std::size_t>(a) + 1, ub = static_cast<std::size_t>(b) + 1;
  // Forward from edge a to edge b: the turns at vertices a+1 … b (mod m).
  const double forward = b > a ? turning[ub] - turning[ua] : turning[m] - turning[ua] + turning[ub];
  return std::min(forward, turning[m] - forward) <= -kPocketTurn;
}

/// The nearest point to x on the loop edges within `radius` (its edge, ends and parameter), and
/// the width of the gap x lies in: the distance to the nearest point of a stick or of any other
/// loop edge seen across the outside (the midpoint of the way there is outside the cage), except
/// an edge whose nearest point is a corner it shares with the first (outside a convex corner both
/// are nearest there), and one whose nearest point lies on the same side of x as the first's (less
/// than 60° apart, seen from x) with nothing of the cage between: the walls of a wide, nearly
/// flat outside wedge, such as where a leg's side turns out to the toe. Walls facing each other
/// across a gap or a wedge narrower than 120° lie farther apart round x.
/// On a closed polygon, a wall also bounds a gap only when the cage between the two walls (the
/// way round it that turns least towards the inside) turns towards the outside by at least 60°:
/// the walls of a pocket of the outside (a gap between two legs, an armpit), not those round a
/// convex part (a leg's side and the sole of its foot, seen past the heel).
struct Nearest {
  double distance = std::numeric_limits<double>::infinity();
  double other = std::numeric_limits<double>::infinity();
  int edge = -1, a = -1, b = -1;
  double t = 0.0;
  Vec2 point = Vec2::Zero();  // the nearest point
  // The other side when it is a loop edge (the far wall of a gap): its ends and parameter.
  int otherA = -1, otherB = -1;
  double otherT = 0.0;
};

Nearest nearestLoopPoint(const CageEdgeGrid& grid, const std::vector<std::array<int, 2>>& edges, const std::vector<char>& onLoop,
                         const CageQueries& cage, const std::vector<double>& turning, const Vec2& x, double radius) {
  Nearest n;
  const Vec2 r(radius, radius);
  auto closest = [&](const Vec2& a, const Vec2& b, double& t) {
    const Vec2 ab = b - a;
    t = std::clamp((x - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
    return (a + t * ab - x).norm();
  };
  grid.forEachEdgeNear(x - r, x + r, [&](int e, const Vec2& a, const Vec2& b) {
    if (!onLoop[static_cast<std::size_t>(e)]) return;
    double t = 0.0;
    const double d = closest(a, b, t);
    if (d < n.distance || (d == n.distance && e < n.edge)) {  // ties: the lower edge, whatever the order of visits
      n.distance = d;
      n.edge = e;
      n.a = edges[static_cast<std::size_t>(e)][0];
      n.b = edges[static_cast<std::size_t>(e)][1];
      n.t = t;
      n.point = a + t * (b - a);
    }
  });
  if (n.edge < 0) return n;
  grid.forEachEdgeNear(x - r, x + r, [&](int e, const Vec2& a, const Vec2& b) {
    if (e == n.edge) return;
    double t = 0.0;
    const double d = closest(a, b, t);
    const int corner = t == 0.0 ? edges[static_cast<std::size_t>(e)][0] : t == 1.0 ? edges[static_cast<std::size_t>(e)][1] : -1;
    if (corner >= 0 && (corner == n.a || corner == n.b)) return;
    // A stick (an edge on no loop) always bounds the gap; a loop edge only seen across the outside,
    // and not when it lies on the same side of x as the first, in plain view.
    if (!(d < n.other)) return;
    const Vec2 q = a + t * (b - a);
    const bool loop = onLoop[static_cast<std::size_t>(e)] != 0;
    if (loop) {
      if (cage.inside(0.5 * (x + q))) return;
      const bool sameSide = (q - x).normalized().dot((n.point - x).normalized()) >= kOneSideCosine;
      if (sameSide && !cage.segmentCrosses(x, q)) return;
      if (!boundsPocket(turning, n.edge, e)) return;
    }
    n.other = d;
    n.otherA = loop ? edges[static_cast<std::size_t>(e)][0] : -1;
    n.otherB = loop ? edges[static_cast<std::size_t>(e)][1] : -1;
    n.otherT = t;
  });
  return n;
}

/// Moving-least-squares shape functions at m over the inside samples within `radius` (linear
/// basis, weight (1 − r²/R²)²): Σ φ_j = 1 and Σ φ_j x_j = m. False when the points within the
/// radius do not determine a plane (fewer than 3, or on one line).
bool fitAt(const SpatialGrid& grid, const Points& Y, const std::vector<Index>& inside, const Vec2& m, double radius,
           std::vector<Index>& rows, std::vector<double>& phi) {
  rows.clear();
  phi.clear();
  std::vector<double> theta;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  const double r2 = radius * radius;
  grid.forEachWithin(m, radius, [&](Index k, double d2) {
    const double q = 1.0 - d2 / r2;
    if (q <= 0.0) return;
    const Eigen::Vector3d bj(1.0, (Y(k, 0) - m.x()) / radius, (Y(k, 1) - m.y()) / radius);
    M.noalias() += q * q * bj * bj.transpose();
    rows.push_back(k);
    theta.push_back(q * q);
  });
  if (rows.size() < 3) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);
  if (!(eig.eigenvalues()(0) > 1e-6 * eig.eigenvalues()(2))) return false;
  const Eigen::Vector3d e = M.ldlt().solve(Eigen::Vector3d::UnitX());  // M symmetric: e1ᵀ M⁻¹ = (M⁻¹ e1)ᵀ
  // Shape functions, with rows mapped to sample indices and sorted (deterministic sums).
  std::vector<std::pair<Index, double>> pairs;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const Index k = rows[j];
    const Eigen::Vector3d bj(1.0, (Y(k, 0) - m.x()) / radius, (Y(k, 1) - m.y()) / radius);
    pairs.emplace_back(inside[static_cast<std::size_t>(k)], theta[j] * e.dot(bj));
  }
  std::sort(pairs.begin(), pairs.end());
  for (std::size_t j = 0; j < pairs.size(); ++j) {
    rows[j] = pairs[j].first;
    phi.push_back(pairs[j].second);
  }
  return true;
}

}  // namespace

ExteriorContinuation::ExteriorContinuation(const SampleSet& S, const Cage& cage, double spacing, const SizingField* sizing,
                                           const ExteriorContinuationOptions& options) {
  if (!hasInterior(cage) || !(spacing > 0.0)) return;
  const Index n = S.size();
  std::vector<Index> inside;
  std::vector<Index> exterior;
  for (Index i = 0; i < n; ++i) (S.kind[static_cast<std::size_t>(i)] == SampleKind::Exterior ? exterior : inside).push_back(i);
  if (exterior.empty() || inside.size() < 3) return;
  Points Y(static_cast<Index>(inside.size()), 2);
  for (std::size_t k = 0; k < inside.size(); ++k) Y.row(static_cast<Index>(k)) = S.X.row(inside[k]);
  const SpatialGrid grid(Y, spacing);
  const auto edges = cageEdges(cage);
  const std::vector<char> onLoop = loopEdgeFlags(cage);
  const CageEdgeGrid edgeGrid(cage, options.bandSpacings * spacing);
  const CageQueries queries(cage);
  const std::vector<double> turning = polygonTurning(cage);
  auto h = [&](const Vec2& x) { return sizing ? (*sizing)(x) : spacing; };

  std::vector<Term> terms(exterior.size());
  std::vector<char> used(exterior.size(), 0);
  parallelFor(static_cast<Index>(exterior.size()), [&](Index k) {
    const Index i = exterior[static_cast<std::size_t>(k)];
    const Vec2 x = S.X.row(i).transpose();
    const double hx = h(x), band = options.bandSpacings * hx;
    const Nearest p = nearestLoopPoint(edgeGrid, edges, onLoop, queries, turning, x, 2.0 * band);
    if (p.edge < 0 || !(p.distance > 0.0)) return;
    auto smoothstep = [](double u) {
      u = std::clamp(u, 0.0, 1.0);
      return u * u * (3.0 - 2.0 * u);
    };
    // α: 1 at the cage, 0 at the band's edge; and 0 in a gap narrower than the band (the other
    // side's inside is as near as this one's: continuing either side would steepen the gap).
    const double width = p.distance + p.other;
    const double alpha = (1.0 - smoothstep(p.distance / band)) * smoothstep(width / band - 1.0);
    // γ: the share of the two-sided blend, in a gap between two loop walls that a graded sampling
    // refines (see the header).
    const double refined =
        sizing && sizing->graded() ? 1.0 - smoothstep(2.0 * (width / sizing->hMax() - options.blendWidth)) : 0.0;
    double gamma = p.otherA >= 0 ? refined * (1.0 - smoothstep(width / band - 2.0)) : 0.0;
    if (!(alpha > 0.0) && !(gamma > 0.0)) return;
    // The odd reflection of the inside through the wall point (1 − t)·c_a + t·c_b, or false
    // when its mirror falls outside the cage or the fit there fails.
    auto reflect = [&](int a, int b, double t, Reflection& r) {
      const Vec2 onEdge = (1.0 - t) * cage.C.row(a).transpose() + t * cage.C.row(b).transpose();
      const Vec2 m = 2.0 * onEdge - x;
      if (!queries.inside(m)) return false;
      double radius = options.fitSpacings * h(m);
      bool ok = false;
      for (int grow = 0; grow < 4 && !ok; ++grow, radius *= 1.5) ok = fitAt(grid, Y, inside, m, radius, r.fitRows, r.fit);
      r.a = a;
      r.b = b;
      r.t = t;
      return ok;
    };
    Reflection nearSide, farSide;
    if (!reflect(p.a, p.b, p.t, nearSide)) return;
    if (gamma > 0.0 && !reflect(p.otherA, p.otherB, p.otherT, farSide)) gamma = 0.0;
    const double s = smoothstep((p.distance / width - kGapWall) / (1.0 - 2.0 * kGapWall));  // the far side's share
    Term& term = terms[static_cast<std::size_t>(k)];
    term.row = i;
    nearSide.c = gamma * (1.0 - s) + (1.0 - gamma) * alpha;
    term.keep = (1.0 - gamma) * (1.0 - alpha);
    if (!(nearSide.c > 0.0)) return;
    term.reflections.push_back(std::move(nearSide));
    if (gamma > 0.0) {
      farSide.c = gamma * s;
      term.reflections.push_back(std::move(farSide));
    }
    used[static_cast<std::size_t>(k)] = 1;
  });
  for (std::size_t k = 0; k < terms.size(); ++k)
    if (used[k]) {
      m_rows.push_back(terms[k].row);
      m_terms.push_back(std::move(terms[k]));
    }
}

std::vector<Index> ExteriorContinuation::sources(std::size_t k) const {
  std::vector<Index> rows;
  for (const Reflection& r : m_terms[k].reflections) rows.insert(rows.end(), r.fitRows.begin(), r.fitRows.end());
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

namespace {

/// Row term.row of W: Σ_r c_r·(2λ(p_r) − ŵ(m_r)) + keep·(its optimized row).
template <class Term>
void continueRow(const Term& term, Weights& W) {
  Eigen::RowVectorXd sum = term.keep * W.row(term.row);
  for (const auto& r : term.reflections) {
    Eigen::RowVectorXd reflected = Eigen::RowVectorXd::Zero(W.cols());
    for (std::size_t j = 0; j < r.fitRows.size(); ++j) reflected.noalias() -= r.fit[j] * W.row(r.fitRows[j]);
    reflected(r.a) += 2.0 * (1.0 - r.t);
    reflected(r.b) += 2.0 * r.t;
    sum += r.c * reflected;
  }
  W.row(term.row) = sum;
}

}  // namespace

void ExteriorContinuation::apply(Weights& W) const {
  parallelFor(static_cast<Index>(m_terms.size()), [&](Index k) { continueRow(m_terms[static_cast<std::size_t>(k)], W); });
}

void ExteriorContinuation::apply(Weights& W, std::span<const Index> only) const {
  std::vector<std::size_t> terms;
  for (Index i : only) {
    const auto it = std::lower_bound(m_rows.begin(), m_rows.end(), i);
    if (it == m_rows.end() || *it != i) throw std::invalid_argument("ExteriorContinuation::apply: row " + std::to_string(i) + " is not continued");
    terms.push_back(static_cast<std::size_t>(it - m_rows.begin()));
  }
  parallelFor(static_cast<Index>(terms.size()), [&](Index k) { continueRow(m_terms[terms[static_cast<std::size_t>(k)]], W); });
}

}  // namespace kc
