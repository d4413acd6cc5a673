#include "kc/core/sizing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "kc/core/cage_edge_grid.h"

namespace kc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Closest points of segments a–b and c–d: parameters s (on a–b) and t (on c–d) in [0, 1].
void closestParameters(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double& s, double& t) {
  const Vec2 u = b - a, v = d - c, w = a - c;
  const double A = u.dot(u), B = u.dot(v), C = v.dot(v), D = u.dot(w), E = v.dot(w);
  const double den = A * C - B * B;
  s = den > 1e-14 * A * C ? std::clamp((B * E - C * D) / den, 0.0, 1.0) : 0.0;
  t = C > 0.0 ? std::clamp((B * s + E) / C, 0.0, 1.0) : 0.0;
  s = A > 0.0 ? std::clamp((B * t - D) / A, 0.0, 1.0) : 0.0;
  // One more half-step of the alternation settles the parallel and end-point cases.
  t = C > 0.0 ? std::clamp((B * s + E) / C, 0.0, 1.0) : 0.0;
}

/// The feature graph: vertices and segments (vertex pairs), features split where they cross or
/// touch so that they share a vertex there.
struct FeatureGraph {
  Points V;
  std::vector<std::array<int, 2>> E;
  std::vector<char> extra;  // per edge: a piece of an extra segment (not a cage edge)
};

FeatureGraph featureGraph(const Cage& cage, std::span<const FeatureSegment> extra) {
  const auto cageE = cageEdges(cage);
  const Index m = cage.size();
  const Index n = static_cast<Index>(extra.size());
  double extent = 0.0;
  if (m > 0)
    extent = std::max(cage.C.col(0).maxCoeff() - cage.C.col(0).minCoeff(), cage.C.col(1).maxCoeff() - cage.C.col(1).minCoeff());
  for (const FeatureSegment& f : extra) extent = std::max({extent, (f.b - f.a).cwiseAbs().maxCoeff()});
  const double eps = 1e-9 * std::max(extent, 1e-300);

  // All segments: cage edges first, then the extra ones, each with its split parameters.
  std::vector<std::array<Vec2, 2>> seg;
  std::vector<std::array<int, 2>> ends;  // vertex ids of the ends
  std::vector<Vec2> verts;
  for (Index i = 0; i < m; ++i) verts.emplace_back(cage.C.row(i));
  for (const auto& [a, b] : cageE) {
    seg.push_back({Vec2(cage.C.row(a)), Vec2(cage.C.row(b))});
    ends.push_back({a, b});
  }
  for (const FeatureSegment& f : extra) {
    const int ia = static_cast<int>(verts.size());
    verts.push_back(f.a);
    verts.push_back(f.b);
    seg.push_back({f.a, f.b});
    ends.push_back({ia, ia + 1});
  }
  // Splits: (parameter, vertex id) per segment. Ends that meet another segment's end or split
  // point are merged into it (union-find `root`): the segments then share that vertex.
  std::vector<std::vector<std::pair<double, int>>> splits(seg.size());
  std::vector<int> parent(verts.size());
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = static_cast<int>(v);
  auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v) v = parent[static_cast<std::size_t>(v)];
    return v;
  };
  auto contact = [&](std::size_t s, std::size_t t) {
    double ps = 0.0, pt = 0.0;
    closestParameters(seg[s][0], seg[s][1], seg[t][0], seg[t][1], ps, pt);
    const Vec2 P = (1.0 - ps) * seg[s][0] + ps * seg[s][1], Q = (1.0 - pt) * seg[t][0] + pt * seg[t][1];
    if ((P - Q).norm() > eps) return;
    // The shared point: an existing end when the contact is at one, else a new vertex.
    int id = -1;
    for (const auto& [S, p] : {std::pair{s, ps}, std::pair{t, pt}}) {
      const double len = (seg[S][1] - seg[S][0]).norm();
      if (p * len <= eps) id = root(ends[S][0]);
      else if ((1.0 - p) * len <= eps) id = root(ends[S][1]);
      if (id >= 0) break;
    }
    if (id < 0) {
      id = static_cast<int>(verts.size());
      verts.push_back(0.5 * (P + Q));
      parent.push_back(id);
    }
    for (const auto& [S, p] : {std::pair{s, ps}, std::pair{t, pt}}) {
      const int e0 = root(ends[S][0]), e1 = root(ends[S][1]);
      if (e0 == id || e1 == id) continue;
      const double len = (seg[S][1] - seg[S][0]).norm();
      if (p * len <= eps) parent[static_cast<std::size_t>(e0)] = id;
      else if ((1.0 - p) * len <= eps) parent[static_cast<std::size_t>(e1)] = id;
      else splits[S].emplace_back(p, id);
    }
  };
  if (n > 0) {
    double cell = std::max(extent / 64.0, 1e-300);
    const CageEdgeGrid grid(cage, cell);
    for (Index k = 0; k < n; ++k) {
      const std::size_t s = cageE.size() + static_cast<std::size_t>(k);
      const Vec2 lo = seg[s][0].cwiseMin(seg[s][1]) - Vec2::Constant(2 * eps), hi = seg[s][0].cwiseMax(seg[s][1]) + Vec2::Constant(2 * eps);
      std::vector<int> seen;
      if (m >= 2)
        grid.forEachEdgeNear(lo, hi, [&](int e, const Vec2&, const Vec2&) { seen.push_back(e); });
      std::sort(seen.begin(), seen.end());
      seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
      for (int e : seen) contact(static_cast<std::size_t>(e), s);
      for (Index l = 0; l < k; ++l) contact(cageE.size() + static_cast<std::size_t>(l), s);
    }
  }
  FeatureGraph g;
  g.V.resize(static_cast<Index>(verts.size()), 2);
  for (std::size_t i = 0; i < verts.size(); ++i) g.V.row(static_cast<Index>(i)) = verts[i].transpose();
  for (std::size_t s = 0; s < seg.size(); ++s) {
    auto& sp = splits[s];
    std::sort(sp.begin(), sp.end());
    int prev = root(ends[s][0]);
    const int last = root(ends[s][1]);
    const char isExtra = s >= cageE.size();
    for (const auto& [p, split] : sp) {
      const int id = root(split);
      if (id == prev || id == last) continue;
      g.E.push_back({prev, id});
      g.extra.push_back(isExtra);
      prev = id;
    }
    if (prev != last) {
      g.E.push_back({prev, last});
      g.extra.push_back(isExtra);
    }
  }
  return g;
}

/// A raw seed: position, spacing and its cone's slope.
struct RawSeed {
  Vec2 p;
  double h, g;
};

/// narrowSpacing with k and n given.
double spacingOfWidth(double width, double k, double narrowWidth, const SizingOptions& o) {
  return std::clamp(std::max(width / k, width - (narrowWidth - 1.0) * o.hMax), o.hMin, o.hMax);
}

/// The spacing at a place of width `width` between two features, one of them extra (a line, a
/// rigid polygon's side) when `extra`: narrowSpacing with k = extraFeatureSamples and
/// n = extraNarrowWidth then.
double pairSpacing(double width, bool extra, const SizingOptions& o) {
  return extra ? spacingOfWidth(width, o.extraFeatureSamples, o.extraNarrowWidth, o) : narrowSpacing(width, o);
}

/// True when the middle of x–y lies outside the closed cage, and so do the points beside it a tenth
/// of |x − y| either way across x–y (a middle on the cage's boundary, as between the two ends of a
/// corner, is not outside).
bool outsideBetween(const CageQueries& cage, const Vec2& x, const Vec2& y) {
  const Vec2 m = 0.5 * (x + y), across = 0.1 * Vec2(y.y() - x.y(), x.x() - y.x());
  return !cage.inside(m) && !cage.inside(m + across) && !cage.inside(m - across);
}

/// For each edge, the cage edges it forms a wedge with (kWedgeDegrees): sharing an end with it,
/// meeting it at less than `degrees`, the outside of the closed cage `cage` between them.
std::vector<std::vector<int>> wedgePartners(const FeatureGraph& g, double degrees, const CageQueries& cage) {
  std::vector<std::vector<int>> partners(g.E.size());
  std::vector<std::vector<int>> incident(static_cast<std::size_t>(g.V.rows()));
  for (std::size_t e = 0; e < g.E.size(); ++e)
    if (!g.extra[e])
      for (int v : g.E[e]) incident[static_cast<std::size_t>(v)].push_back(int(e));
  const double cosWedge = std::cos(degrees * std::numbers::pi / 180.0);
  for (std::size_t v = 0; v < incident.size(); ++v) {
    const Vec2 V = g.V.row(Index(v));
    auto away = [&](int e) {  // from V along edge e
      const auto& ends = g.E[std::size_t(e)];
      return Vec2(Vec2(g.V.row(ends[0] == int(v) ? ends[1] : ends[0])) - V);
    };
    for (std::size_t i = 0; i < incident[v].size(); ++i)
      for (std::size_t j = i + 1; j < incident[v].size(); ++j) {
        const int s = incident[v][i], t = incident[v][j];
        const Vec2 ua = away(s), ub = away(t);
        const double la = ua.norm(), lb = ub.norm();
        if (!(la > 0.0 && lb > 0.0) || !(ua.dot(ub) > cosWedge * la * lb)) continue;
        // A point on the bisector just off the shared vertex lies between the two edges.
        if (cage.inside(V + 1e-3 * std::min(la, lb) * (ua / la + ub / lb).normalized())) continue;
        partners[std::size_t(s)].push_back(t);
        partners[std::size_t(t)].push_back(s);
      }
  }
  return partners;
}

/// Seeds where the spacing of a gap (pairSpacing) is below hMax: every half local spacing along
/// each segment, and at vertices (their shortest incident segment). `cage`: the closed cage's
/// queries (null for an open one): without o.outsideGaps a gap whose middle lies outside it does
/// not count, nor does a wedge (whose middle always does).
std::vector<RawSeed> rawSeeds(const FeatureGraph& g, const SizingOptions& o, const CageQueries* cage) {
  std::vector<RawSeed> seeds;
  // Widths at or above `below` leave hMax for either kind of pair.
  const double below = std::max({o.narrowWidth, o.extraNarrowWidth, o.outsideNarrowWidth}) * o.hMax;
  if (g.E.empty() || !(below > 0.0)) return seeds;
  Cage fc;
  fc.C = g.V;
  fc.edges = g.E;
  fc.closed = false;
  const double R = 2.0 * below;
  const CageEdgeGrid grid(fc, R);
  std::vector<double> shortest(static_cast<std::size_t>(g.V.rows()), kInf);
  std::vector<char> used(static_cast<std::size_t>(g.V.rows()), 0), onExtra(static_cast<std::size_t>(g.V.rows()), 0);
  for (std::size_t e = 0; e < g.E.size(); ++e) {
    const auto [a, b] = g.E[e];
    const double len = (g.V.row(a) - g.V.row(b)).norm();
    for (int v : {a, b}) {
      shortest[static_cast<std::size_t>(v)] = std::min(shortest[static_cast<std::size_t>(v)], len);
      used[static_cast<std::size_t>(v)] = 1;
      onExtra[static_cast<std::size_t>(v)] |= g.extra[e];
    }
  }
  for (Index v = 0; v < g.V.rows(); ++v) {
    const std::size_t u = static_cast<std::size_t>(v);
    const double h = used[u] ? pairSpacing(shortest[u], onExtra[u] != 0, o) : o.hMax;
    if (h < o.hMax) seeds.push_back({g.V.row(v), h, o.gradation});
  }

  // At x on segment s: the distance to the nearest segment sharing no vertex with s (`all`), and
  // the spacing the gaps that count ask for (`h`: with outsideGaps, not those whose middle lies
  // outside the cage), the smallest over the pairs within R.
  struct Lfs {
    double all, h;
    bool apart;  // h is that of a gap between two parts (outsideSpacing), not a wedge
  };
  const std::vector<std::vector<int>> wedges =
      o.outsideGaps && cage && o.wedgeDegrees > 0.0 ? wedgePartners(g, o.wedgeDegrees, *cage) : std::vector<std::vector<int>>(g.E.size());
  auto lfs = [&](const Vec2& x, int s) {
    const auto& es = g.E[static_cast<std::size_t>(s)];
    Lfs best{R, o.hMax, false};
    grid.forEachEdgeNear(x - Vec2::Constant(R), x + Vec2::Constant(R), [&](int t, const Vec2& a, const Vec2& b) {
      if (t == s) return;
      const auto& et = g.E[static_cast<std::size_t>(t)];
      const bool wedge = et[0] == es[0] || et[0] == es[1] || et[1] == es[0] || et[1] == es[1];
      const auto& partners = wedges[std::size_t(s)];
      if (wedge && std::find(partners.begin(), partners.end(), t) == partners.end()) return;
      const double d = pointSegmentDistance(x, a, b);
      best.all = std::min(best.all, d);
      const double finest = wedge ? o.wedgeFinest * o.hMax : 0.0;  // a wedge's spacing stops there
      const bool extra = g.extra[std::size_t(s)] || g.extra[std::size_t(t)];
      double h = std::max(finest, pairSpacing(d, extra, o));
      bool apart = false;
      if (!extra && cage && o.outsideGaps) {  // a gap between two parts (a wedge's middle always lies outside)
        const double outside = std::max(finest, outsideSpacing(d, o));
        if (outside < std::min(h, best.h) && (wedge || outsideBetween(*cage, x, closestPointOnSegment(x, a, b)))) {
          h = outside;
          apart = !wedge;
        }
      }
      if (h >= best.h) return;
      if (!wedge && !o.outsideGaps && cage && outsideBetween(*cage, x, closestPointOnSegment(x, a, b))) return;
      best.h = h;
      best.apart = apart;
    });
    return best;
  };
  for (std::size_t s = 0; s < g.E.size(); ++s) {
    const Vec2 A = g.V.row(g.E[s][0]), B = g.V.row(g.E[s][1]);
    const double L = (B - A).norm();
    if (!(L > 0.0)) continue;
    double t = 0.0;
    for (;;) {
      const Vec2 x = A + (t / L) * (B - A);
      const Lfs l = lfs(x, static_cast<int>(s));
      if (l.h < o.hMax) seeds.push_back({x, l.h, l.apart && l.h < o.fineBelow * o.hMax ? o.fineGradation : o.gradation});
      if (t >= L) break;
      // The distance to every other segment is 1-Lipschitz along the segment: where it is far
      // above `below` the walk can jump (the spacing may jump where a gap's middle crosses the cage).
      t = std::min(L, t + std::max(0.5 * l.h, l.all - below));
    }
  }
  return seeds;
}

}  // namespace

SizingField SizingField::uniform(double hMax) {
  return SizingField(hMax, kSizingGradation, Points(0, 2), Eigen::VectorXd(0));
}

SizingField::SizingField(double hMax, double gradation, const Points& P, const Eigen::VectorXd& H, SizingForm form,
                         const Eigen::VectorXd& G)
    : m_hMax(hMax), m_g(gradation), m_form(form), m_P(P), m_H(H), m_G(G) {
  if (!(hMax > 0.0) || !std::isfinite(hMax)) throw std::invalid_argument("sizing: hMax must be positive and finite");
  if (!(gradation > 0.0 && gradation <= 0.5)) throw std::invalid_argument("sizing: gradation must be in (0, 0.5]");
  if (P.rows() != H.size()) throw std::invalid_argument("sizing: one size per seed");
  if (!P.allFinite() || !H.allFinite()) throw std::invalid_argument("sizing: seeds must be finite");
  if (H.size() > 0 && (!(H.minCoeff() > 0.0) || H.maxCoeff() > hMax))
    throw std::invalid_argument("sizing: seed sizes must be in (0, hMax]");
  if (G.size() != 0 && G.size() != H.size()) throw std::invalid_argument("sizing: one slope per seed, or none");
  if (G.size() > 0 && (!G.allFinite() || G.minCoeff() < gradation || G.maxCoeff() > 0.5))
    throw std::invalid_argument("sizing: seed slopes must be in [gradation, 0.5]");
  if (G.size() > 0 && G.minCoeff() == G.maxCoeff() && G(0) == gradation) m_G.resize(0);  // one slope
  buildGrid();
}

void SizingField::buildGrid() {
  m_start.clear();
  m_items.clear();
  m_cellLow.clear();
  m_nx = m_ny = 0;
  if (m_P.rows() == 0) return;
  // Seeds farther than m_reach from x leave h(x) = h̃(x) = hMax (the smooth profile's cones reach 2·hMax).
  // A cone's value at distance d is at least (1 − g_i/2)·h_i + g·d (g the least slope).
  m_tipLow = kInf;
  for (Index i = 0; i < m_P.rows(); ++i) m_tipLow = std::min(m_tipLow, (1.0 - 0.5 * slope(static_cast<int>(i))) * m_H(i));
  m_reach = ((m_form == SizingForm::Smooth ? 2.0 : 1.0) * m_hMax - m_tipLow) / m_g;
  const double x0 = m_P.col(0).minCoeff(), y0 = m_P.col(1).minCoeff();
  const double w = m_P.col(0).maxCoeff() - x0, h = m_P.col(1).maxCoeff() - y0;
  // Cells of an eighth of the reach: queries scan rings of cells outwards and stop once no seed
  // farther out can give a smaller h.
  m_cell = std::max({m_reach / 8.0, w / 1024.0, h / 1024.0, 1e-9});
  m_x0 = x0;
  m_y0 = y0;
  m_nx = static_cast<int>(w / m_cell) + 1;
  m_ny = static_cast<int>(h / m_cell) + 1;
  std::vector<int> count(static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny) + 1, 0);
  auto cellOf = [&](Index i) {
    const int cx = std::min(m_nx - 1, static_cast<int>((m_P(i, 0) - m_x0) / m_cell));
    const int cy = std::min(m_ny - 1, static_cast<int>((m_P(i, 1) - m_y0) / m_cell));
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(m_nx) + static_cast<std::size_t>(cx);
  };
  for (Index i = 0; i < m_P.rows(); ++i) ++count[cellOf(i) + 1];
  for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  m_start = count;
  m_items.resize(static_cast<std::size_t>(m_P.rows()));
  for (Index i = 0; i < m_P.rows(); ++i) m_items[static_cast<std::size_t>(count[cellOf(i)]++)] = static_cast<int>(i);
  // Each cell's lowest rounded cone tip: a query skips the cells this bound rules out.
  m_cellLow.assign(static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny), kInf);
  for (Index i = 0; i < m_P.rows(); ++i) {
    double& low = m_cellLow[cellOf(i)];
    low = std::min(low, (1.0 - 0.5 * slope(static_cast<int>(i))) * m_H(i));
  }
}

template <class Bound, class Visit>
void SizingField::scanSeeds(const Vec2& x, Bound bound, Visit visit) const {
  if (m_P.rows() == 0) return;
  const double hLow = m_tipLow;  // a lower bound of every rounded cone's tip
  const int cx = static_cast<int>(std::floor((x.x() - m_x0) / m_cell)), cy = static_cast<int>(std::floor((x.y() - m_y0) / m_cell));
  // Cells at Chebyshev ring r lie at least (r − 1)·cell away.
  const int rings = static_cast<int>(std::ceil(m_reach / m_cell)) + 1;
  // Distance from x to the grid (x may lie outside it).
  const double outside = std::max({m_x0 - x.x(), x.x() - (m_x0 + m_nx * m_cell), m_y0 - x.y(), x.y() - (m_y0 + m_ny * m_cell), 0.0});
  if (hLow + m_g * outside >= bound()) return;
  for (int r = 0; r <= rings + static_cast<int>(outside / m_cell) + 1; ++r) {
    if (hLow + m_g * (std::max(r - 1, 0) * m_cell) >= bound()) break;
    for (int j = cy - r; j <= cy + r; ++j) {
      if (j < 0 || j >= m_ny) continue;
      const bool edgeRow = j == cy - r || j == cy + r;
      for (int i = cx - r; i <= cx + r; i += edgeRow ? 1 : 2 * r) {
        if (i >= 0 && i < m_nx) {
          const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(m_nx) + static_cast<std::size_t>(i);
          // The distance from x to the cell: its seeds' cones lie at least cellLow + g·that above 0.
          const double cellX = m_x0 + i * m_cell, cellY = m_y0 + j * m_cell;
          const double dx = std::max({cellX - x.x(), x.x() - (cellX + m_cell), 0.0});
          const double dy = std::max({cellY - x.y(), x.y() - (cellY + m_cell), 0.0});
          if (m_cellLow[c] + m_g * std::sqrt(dx * dx + dy * dy) < bound())
            for (int k = m_start[c]; k < m_start[c + 1]; ++k) visit(m_items[static_cast<std::size_t>(k)]);
        }
        if (r == 0) break;
      }
    }
  }
}

double SizingField::minForm(const Vec2& x, Vec2& gradient) const {
  double best = m_hMax;
  int arg = -1;
  scanSeeds(
      x, [&] { return best; },
      [&](int s) {
        const double v = m_H(s) + slope(s) * (x - Vec2(m_P.row(s))).norm();
        if (v < best) {
          best = v;
          arg = s;
        }
      });
  if (arg >= 0) {
    const Vec2 d = x - Vec2(m_P.row(arg));
    const double len = d.norm();
    if (len > 0.0) gradient = (slope(arg) / len) * d;
  }
  return best;
}

double SizingField::smoothForm(const Vec2& x, Vec2& gradient) const {
  // S = 1 + Σ τ(a_i) (hMax/a_i)^p over the seeds with a_i < 2·hMax (τ = 0 beyond); h = hMax·S^(−1/p).
  constexpr double p = kSizingSoftness;
  double S = 1.0;
  Vec2 dS = Vec2::Zero();
  const double cut = 2.0 * m_hMax;
  scanSeeds(x, [&] { return cut; }, [&](int s) {
    const Vec2 d = x - Vec2(m_P.row(s));
    const double eps = 0.5 * m_H(s), root = std::sqrt(d.squaredNorm() + eps * eps);
    const double gs = slope(s), a = m_H(s) + gs * (root - eps);
    if (a >= cut) return;
    double tau = 1.0, dtau = 0.0;  // τ(a) and dτ/da: 1 − smootherstep over [hMax, 2·hMax]
    if (a > m_hMax) {
      const double t = a / m_hMax - 1.0;
      tau = 1.0 - t * t * t * (10.0 - t * (15.0 - 6.0 * t));
      dtau = -30.0 * t * t * (1.0 - t) * (1.0 - t) / m_hMax;
    }
    const double r = m_hMax / a, r2 = r * r, r4 = r2 * r2, rp = r4 * r4;
    static_assert(p == 8.0, "rp is (hMax/a)^p by repeated squaring");
    S += tau * rp;
    // d/da [τ (hMax/a)^p] = (τ' − p τ / a) (hMax/a)^p;  ∇a = g (x − p_i) / root.
    dS += ((dtau - p * tau / a) * rp * gs / root) * d;
  });
  const double h = m_hMax * std::pow(S, -1.0 / p);
  gradient = (-h / (p * S)) * dS;
  return h;
}

double SizingField::valueAndGradient(const Vec2& x, Vec2& gradient) const {
  gradient.setZero();
  return m_P.rows() == 0 ? m_hMax : minForm(x, gradient);
}

double SizingField::profile(const Vec2& x, Vec2* gradient) const {
  Vec2 g = Vec2::Zero();
  const double h = m_P.rows() == 0 ? m_hMax : m_form == SizingForm::Smooth ? smoothForm(x, g) : minForm(x, g);
  if (gradient) *gradient = g;
  return h;
}

Eigen::VectorXd SizingField::profileAt(const Points& X) const {
  Eigen::VectorXd h(X.rows());
  for (Index i = 0; i < X.rows(); ++i) h(i) = profile(X.row(i));
  return h;
}

double SizingField::operator()(const Vec2& x) const {
  Vec2 unused;
  return valueAndGradient(x, unused);
}

Eigen::VectorXd SizingField::at(const Points& X) const {
  Eigen::VectorXd h(X.rows());
  for (Index i = 0; i < X.rows(); ++i) h(i) = (*this)(X.row(i));
  return h;
}

double narrowSpacing(double width, const SizingOptions& o) { return spacingOfWidth(width, o.featureSamples, o.narrowWidth, o); }

double outsideSpacing(double width, const SizingOptions& o) {
  return width < o.outsideNarrowWidth * o.hMax ? std::clamp(width / o.outsideFeatureSamples, o.hMin, o.hMax) : o.hMax;
}

SizingField featureSizing(const Cage& cage, std::span<const FeatureSegment> extra, const SizingOptions& o) {
  if (!(o.hMax > 0.0) || !std::isfinite(o.hMax)) throw std::invalid_argument("sizing: hMax must be positive and finite");
  if (!(o.hMin > 0.0) || o.hMin > o.hMax) throw std::invalid_argument("sizing: hMin must be in (0, hMax]");
  for (double k : {o.featureSamples, o.extraFeatureSamples, o.outsideFeatureSamples})
    if (!(k > 0.0) || !std::isfinite(k))
      throw std::invalid_argument("sizing: featureSamples, extraFeatureSamples and outsideFeatureSamples must be positive");
  for (const FeatureSegment& f : extra)
    if (!f.a.allFinite() || !f.b.allFinite()) throw std::invalid_argument("sizing: feature segments must be finite");
  for (double n : {o.narrowWidth, o.extraNarrowWidth, o.outsideNarrowWidth})
    if (!(n >= 1.0) || !std::isfinite(n))
      throw std::invalid_argument("sizing: narrowWidth, extraNarrowWidth and outsideNarrowWidth must be at least 1");
  if (!(o.gradation > 0.0 && o.gradation <= 0.5) || !(o.fineGradation >= o.gradation && o.fineGradation <= 0.5) ||
      !(o.fineBelow >= 0.0))
    throw std::invalid_argument(
        "sizing: gradation must be in (0, 0.5], fineGradation in [gradation, 0.5] and fineBelow at least 0");
  if (!(o.wedgeDegrees >= 0.0 && o.wedgeDegrees < 90.0) || !(o.wedgeFinest > 0.0 && o.wedgeFinest <= 1.0))
    throw std::invalid_argument("sizing: wedgeDegrees must be in [0, 90) and wedgeFinest in (0, 1]");
  std::optional<CageQueries> inside;
  if (cage.closed && cage.size() >= 3) inside.emplace(cage);
  const std::vector<RawSeed> raw = rawSeeds(featureGraph(cage, extra), o, inside ? &*inside : nullptr);
  Points P(static_cast<Index>(raw.size()), 2);
  Eigen::VectorXd H(static_cast<Index>(raw.size())), G(static_cast<Index>(raw.size()));
  for (std::size_t i = 0; i < raw.size(); ++i) {
    P.row(static_cast<Index>(i)) = raw[i].p.transpose();
    H(static_cast<Index>(i)) = raw[i].h;
    G(static_cast<Index>(i)) = raw[i].g;
  }
  return SizingField(o.hMax, o.gradation, P, H, SizingForm::Smooth, G);
}

std::vector<double> segmentDivision(const Vec2& a, const Vec2& b, const SizingField& h) {
  const double L = (b - a).norm();
  std::vector<double> t;
  if (!h.graded() || !(L > 0.0)) {
    const Index n = std::max<Index>(1, static_cast<Index>(std::llround(L / h.hMax())));
    for (Index k = 0; k <= n; ++k) t.push_back(static_cast<double>(k) / static_cast<double>(n));
    return t;
  }
  // ∫ ds / h by the midpoint rule on steps of a quarter of the local spacing.
  std::vector<double> s{0.0}, cum{0.0};
  while (s.back() < L) {
    const double x = s.back();
    const double step = std::min(L - x, 0.25 * h(a + (x / L) * (b - a)));
    const double mid = x + 0.5 * step;
    cum.push_back(cum.back() + step / h(a + (mid / L) * (b - a)));
    s.push_back(x + step);
  }
  s.back() = L;
  const double total = cum.back();
  const Index n = std::max<Index>(1, static_cast<Index>(std::llround(total)));
  t.push_back(0.0);
  std::size_t j = 1;
  for (Index k = 1; k < n; ++k) {
    const double target = total * static_cast<double>(k) / static_cast<double>(n);
    while (j + 1 < cum.size() && cum[j] < target) ++j;
    const double f = (target - cum[j - 1]) / std::max(cum[j] - cum[j - 1], 1e-300);
    t.push_back(std::clamp((s[j - 1] + f * (s[j] - s[j - 1])) / L, 0.0, 1.0));
  }
  t.push_back(1.0);
  return t;
}


}  // namespace kc
