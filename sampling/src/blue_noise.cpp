#include "kc/sampling/blue_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include "kc/core/cage_edge_grid.h"

namespace kc::sampling {
namespace {

/// Uniform double in [0, 1) from 53 random bits (portable, unlike std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/// Cells of side about c over rect: nx × ny, stretched slightly to tile it exactly.
struct CellGrid {
  Index nx = 1, ny = 1;
  double cx = 0.0, cy = 0.0;
};
CellGrid cellGridOf(const Rect& rect, double c) {
  CellGrid g;
  g.nx = std::max<Index>(1, static_cast<Index>(std::ceil(rect.width() / c)));
  g.ny = std::max<Index>(1, static_cast<Index>(std::ceil(rect.height() / c)));
  g.cx = rect.width() / static_cast<double>(g.nx);
  g.cy = rect.height() / static_cast<double>(g.ny);
  return g;
}

/// One jittered point per cell of side c over rect; rows in cell order. Both coordinates are
/// drawn for every cell so the stream does not depend on which points are kept. With `keep`,
/// only the points of cells that meet it are returned (the stream is the same: the other rows'
/// draws are discarded).
std::vector<Vec2> jitteredCells(const Rect& rect, double c, std::mt19937_64& rng, const Rect* keep = nullptr) {
  const CellGrid g = cellGridOf(rect, c);
  Index i0 = 0, i1 = g.nx, j0 = 0, j1 = g.ny;
  if (keep) {
    auto clampIndex = [](double v, Index n) { return std::clamp<Index>(static_cast<Index>(std::floor(v)), 0, n); };
    i0 = clampIndex((keep->x0 - rect.x0) / g.cx, g.nx);
    i1 = clampIndex((keep->x1 - rect.x0) / g.cx + 1.0, g.nx);
    j0 = clampIndex((keep->y0 - rect.y0) / g.cy, g.ny);
    j1 = clampIndex((keep->y1 - rect.y0) / g.cy + 1.0, g.ny);
  }
  std::vector<Vec2> pts;
  pts.reserve(static_cast<std::size_t>(std::max<Index>(0, (i1 - i0) * (j1 - j0))));
  rng.discard(static_cast<unsigned long long>(2 * g.nx * j0));
  for (Index j = j0; j < j1; ++j) {
    rng.discard(static_cast<unsigned long long>(2 * i0));
    for (Index i = i0; i < i1; ++i) {
      const double u = uniform01(rng), v = uniform01(rng);
      pts.emplace_back(rect.x0 + (static_cast<double>(i) + u) * g.cx, rect.y0 + (static_cast<double>(j) + v) * g.cy);
    }
    rng.discard(static_cast<unsigned long long>(2 * (g.nx - i1)));
  }
  return pts;
}

/// splitmix64: a portable hash of one 64-bit word (the per-cell random stream of the graded start).
std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// A leaf of the graded start is split while its side exceeds kLeafSpacings·√cellArea·h(centre),
/// so a leaf expects about 1 to 4 samples: every leaf of a narrow corridor gets at least one. With
/// leaves of one sample or less, a corridor a few samples wide starts with runs of empty leaves,
/// and the relaxation spreads its samples along it over O(n²) iterations.
constexpr double kLeafSpacings = 2.0;

/// Visits the cells of the graded start: root cells of side c0 = √cellArea·hMax over `rect`
/// (those meeting `keep` when given), each split into four while its side exceeds
/// kLeafSpacings·√cellArea·h(centre); f(cell rectangle, expected count, id) for every leaf, the
/// expected count side² / (cellArea·h(centre)²) of its samples (so the expected density is
/// 1/(cellArea·h²)), h(centre) and its id. Leaves below a side of hMin·√cellArea/2 are not split further.
template <class F>
void gradedCells(const Rect& rect, const SizingField& sizing, double cellArea, const Rect* keep, F&& f) {
  const double root = std::sqrt(cellArea);
  const CellGrid g = cellGridOf(rect, root * sizing.hMax());
  const double floorSide = 0.5 * root * sizing.hMin();
  auto visit = [&](auto&& self, const Rect& cell, std::uint64_t id) -> void {
    if (keep && (cell.x1 < keep->x0 || cell.x0 > keep->x1 || cell.y1 < keep->y0 || cell.y0 > keep->y1)) return;
    const Vec2 centre(0.5 * (cell.x0 + cell.x1), 0.5 * (cell.y0 + cell.y1));
    const double hc = sizing(centre);
    const double side = std::max(cell.width(), cell.height());
    if (side > kLeafSpacings * root * hc && side > floorSide) {
      const double xm = centre.x(), ym = centre.y();
      const std::uint64_t child = splitmix(id);
      self(self, {cell.x0, cell.y0, xm, ym}, child + 1);
      self(self, {xm, cell.y0, cell.x1, ym}, child + 2);
      self(self, {cell.x0, ym, xm, cell.y1}, child + 3);
      self(self, {xm, ym, cell.x1, cell.y1}, child + 4);
      return;
    }
    f(cell, cell.area() / (cellArea * hc * hc), hc, id);
  };
  for (Index j = 0; j < g.ny; ++j)
    for (Index i = 0; i < g.nx; ++i) {
      const Rect cell{rect.x0 + static_cast<double>(i) * g.cx, rect.y0 + static_cast<double>(j) * g.cy,
                      rect.x0 + static_cast<double>(i + 1) * g.cx, rect.y0 + static_cast<double>(j + 1) * g.cy};
      const auto root = static_cast<std::uint64_t>(j * g.nx + i);
      if (keep && (cell.x1 < keep->x0 || cell.x0 > keep->x1 || cell.y1 < keep->y0 || cell.y0 > keep->y1)) continue;
      visit(visit, cell, root);
    }
}

/// Which side of the cage points near a known point lie on: the known point's side, flipped by
/// each loop edge (loopEdges: sticks bound nothing) that the segment between them crosses, found
/// through a grid of those edges, O(edges near the segment) a query instead of the O(m) even-odd
/// test. A segment through a vertex or touching an edge falls back to the even-odd test.
class LoopParity {
 public:
  LoopParity(const Cage& cage, double cell) : m_loops{cage.C, loopEdges(cage), false}, m_grid(m_loops, cell) {}

  bool inside(const Vec2& from, bool fromInside, const Vec2& to, const CageQueries& exact) const {
    std::array<int, 16> seen{};
    std::size_t nSeen = 0;
    bool inside = fromInside, degenerate = false;
    auto orient = [](const Vec2& a, const Vec2& b, const Vec2& c) {
      return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    };
    m_grid.forEachEdgeNear(from.cwiseMin(to), from.cwiseMax(to), [&](int e, const Vec2& a, const Vec2& b) {
      if (degenerate) return;
      if (std::find(seen.begin(), seen.begin() + static_cast<std::ptrdiff_t>(nSeen), e) !=
          seen.begin() + static_cast<std::ptrdiff_t>(nSeen))
        return;
      if (nSeen == seen.size()) {  // more edges than expected near one short segment
        degenerate = true;
        return;
      }
      seen[nSeen++] = e;
      const double s1 = orient(from, to, a), s2 = orient(from, to, b), s3 = orient(a, b, from), s4 = orient(a, b, to);
      if (s1 == 0.0 || s2 == 0.0 || s3 == 0.0 || s4 == 0.0) {
        degenerate = true;
        return;
      }
      if ((s1 > 0.0) != (s2 > 0.0) && (s3 > 0.0) != (s4 > 0.0)) inside = !inside;
    });
    return degenerate ? exact.inside(to) : inside;
  }

 private:
  Cage m_loops;
  CageEdgeGrid m_grid;
};

Points toPoints(const std::vector<Vec2>& v) {
  Points P(static_cast<Index>(v.size()), 2);
  for (std::size_t k = 0; k < v.size(); ++k) P.row(static_cast<Index>(k)) = v[k].transpose();
  return P;
}

}  // namespace

double blueNoiseCountEstimate(const Rect& domain, double h, double cellArea) {
  const double perimeter = 2.0 * (domain.width() + domain.height());
  return domain.area() / (cellArea * h * h) + perimeter / h + 4.0;
}

double gradedCountEstimate(const Rect& domain, const SizingField& sizing, double cellArea) {
  double n = 0.0;
  gradedCells(domain, sizing, cellArea, nullptr, [&](const Rect&, double p, double, std::uint64_t) { n += p; });
  return n;
}

Points gradedStart(const Cage& cage, const Rect& domain, const SizingField& sizing, double cellArea, std::uint64_t seed,
                   Index& interiorCount, const Cage* obstacles, const Rect* cellGrid) {
  const bool anchored = cellGrid && cellGrid->area() > 0.0;
  const CageEdgeGrid locator(obstacles ? *obstacles : cage, sizing.hMax());
  const CageQueries queries(cage);
  const LoopParity parity(cage, sizing.hMax());
  std::vector<Vec2> inside, outside;
  // The inside and the outside each get as many samples as their running sum of expected counts,
  // in the quadtree's order, passes whole numbers: the count over any run of neighbouring leaves,
  // on either side of the cage, is then within one of its expectation (no Poisson clumps and
  // holes for the relaxation to smooth out; a corridor between two parts of the cage, which its
  // samples cannot leave sideways, starts with the count its area needs). A leaf that the cage or
  // the domain's boundary comes near is split between the sides by the fractions of a stratified
  // 4×4 set of probes on each (probes within h/2 of them count for neither: the samples there
  // are dropped). The sums start at random offsets; positions are random in the leaf.
  double carryIn = static_cast<double>(splitmix(seed) >> 11) * 0x1.0p-53;
  double carryOut = static_cast<double>(splitmix(seed ^ 0x5bd1e995u) >> 11) * 0x1.0p-53;
  gradedCells(anchored ? *cellGrid : domain, sizing, cellArea, anchored ? &domain : nullptr,
              [&](const Rect& cell, double expected, double hc, std::uint64_t id) {
                const std::uint64_t base = splitmix(seed ^ splitmix(id));
                auto draw = [&](std::uint64_t k) { return static_cast<double>(splitmix(base + k) >> 11) * 0x1.0p-53; };
                auto at = [&](double u, double v) { return Vec2(cell.x0 + u * cell.width(), cell.y0 + v * cell.height()); };
                const Vec2 centre = at(0.5, 0.5);
                const bool centreInside = queries.inside(centre);
                // h ≤ hc + g·r ≤ hc + r/2 in the leaf (g ≤ 1/2): nothing in it lies within h/2 of
                // the obstacles or the domain's side when they are this far from the centre.
                const double r = 0.5 * std::hypot(cell.width(), cell.height()), clear = r + 0.5 * (hc + 0.5 * r);
                double in = centreInside ? 1.0 : 0.0, out = 1.0 - in;
                const bool near = locator.distance(centre, clear) < clear || domain.insideDistance(centre) < clear;
                if (near) {
                  constexpr int kProbes = 4;
                  in = out = 0.0;
                  for (int a = 0; a < kProbes; ++a)
                    for (int b = 0; b < kProbes; ++b) {
                      // Draws 1000 on: past the positions' (a leaf wants at most 6 samples, so
                      // at most 96 tries draw 1 to 192).
                      const std::uint64_t k = 1000 + 2 * static_cast<std::uint64_t>(a * kProbes + b);
                      const Vec2 q = at((a + draw(k)) / kProbes, (b + draw(k + 1)) / kProbes);
                      if (domain.insideDistance(q) < 0.5 * hc || locator.distance(q, 0.5 * hc) < 0.5 * hc) continue;
                      (parity.inside(centre, centreInside, q, queries) ? in : out) += 1.0 / (kProbes * kProbes);
                    }
                }
                carryIn += expected * in;
                carryOut += expected * out;
                const int wantIn = static_cast<int>(carryIn), wantOut = static_cast<int>(carryOut);
                carryIn -= wantIn;
                carryOut -= wantOut;
                int gotIn = 0, gotOut = 0;
                const int tries = near ? 16 * (wantIn + wantOut) : wantIn + wantOut;
                for (int m = 0; m < tries && (gotIn < wantIn || gotOut < wantOut); ++m) {
                  const Vec2 p = at(draw(1 + 2 * static_cast<std::uint64_t>(m)), draw(2 + 2 * static_cast<std::uint64_t>(m)));
                  if (!near) {
                    (centreInside ? inside : outside).push_back(p);
                    ++(centreInside ? gotIn : gotOut);
                    continue;
                  }
                  const double minDistance = 0.5 * sizing(p);
                  if (domain.insideDistance(p) < minDistance) continue;
                  if (locator.distance(p, minDistance) < minDistance) continue;
                  if (queries.inside(p)) {
                    if (gotIn < wantIn) inside.push_back(p), ++gotIn;
                  } else if (gotOut < wantOut) {
                    outside.push_back(p), ++gotOut;
                  }
                }
              });
  interiorCount = static_cast<Index>(inside.size());
  inside.insert(inside.end(), outside.begin(), outside.end());
  return toPoints(inside);
}

Points jitteredStart(const Cage& cage, const Rect& domain, double h, double cellArea, std::uint64_t seed,
                     Index& interiorCount, const Cage* obstacles, const Rect* cellGrid) {
  std::mt19937_64 rng(seed);
  const double c = h * std::sqrt(cellArea);
  const bool anchored = cellGrid && cellGrid->area() > 0.0;
  const auto candidates = anchored ? jitteredCells(*cellGrid, c, rng, &domain) : jitteredCells(domain, c, rng);
  const CageEdgeGrid locator(obstacles ? *obstacles : cage, h);
  const double minDistance = 0.5 * h;
  const CageQueries queries(cage);
  std::vector<Vec2> inside, outside;
  for (const Vec2& p : candidates) {
    if (domain.insideDistance(p) < minDistance) continue;
    if (locator.distance(p, minDistance) < minDistance) continue;
    (queries.inside(p) ? inside : outside).push_back(p);
  }
  interiorCount = static_cast<Index>(inside.size());
  inside.insert(inside.end(), outside.begin(), outside.end());
  return toPoints(inside);
}

BlueNoiseResult blueNoiseSample(const Cage& cage, const Rect& domain, double h, std::uint64_t seed,
                                const BlueNoiseOptions& options, std::span<const StructureLine> lines) {
  BlueNoiseResult result;
  SampleSet& S = result.samples;
  const SizingField* sizing = options.relax.sizing && options.relax.sizing->graded() ? options.relax.sizing : nullptr;
  const SizingField local = sizing ? *sizing : SizingField::uniform(h);
  S = boundarySamples(cage, local);
  appendLineSamples(S, lines, local);
  const Cage obstacles = obstacleEdges(cage, lines);
  const Points frame = dropNearCage(cage, framePoints(domain, local), local, 0.5);
  appendSamples(S, frame, SampleKind::Exterior);
  result.frameCount = frame.rows();
  const Index firstFree = S.size();

  const Points start = sizing ? gradedStart(cage, domain, *sizing, options.cellArea, seed, result.interiorCount, &obstacles,
                                            &options.cellGrid)
                              : jitteredStart(cage, domain, h, options.cellArea, seed, result.interiorCount, &obstacles,
                                              &options.cellGrid);
  result.exteriorCount = start.rows() - result.interiorCount;
  appendSamples(S, start.topRows(result.interiorCount), SampleKind::Interior);
  appendSamples(S, start.bottomRows(result.exteriorCount), SampleKind::Exterior);

  InverseMeanShiftOptions relax = options.relax;
  relax.spacing = h;
  RelaxRegion region;
  region.cage = &obstacles;
  region.domain = domain;
  result.relax = relaxInverseMeanShift(S.X, firstFree, region, relax);
  return result;
}

Points blueNoiseRectangle(Index count, const Rect& rect, std::uint64_t seed, InverseMeanShiftOptions relax,
                          InverseMeanShiftReport* report) {
  if (count <= 0) throw std::invalid_argument("blue noise rectangle: count must be positive");
  if (!(rect.width() > 0.0 && rect.height() > 0.0) || !std::isfinite(rect.area()))
    throw std::invalid_argument("blue noise rectangle: the rectangle must have positive, finite size");
  const double h = std::sqrt(rect.area() / (static_cast<double>(count) * kHexCellFactor));
  std::mt19937_64 rng(seed);
  // Cells of area area/count (whole rows and columns, so at least count), then drop random extras.
  const double c = std::sqrt(rect.area() / static_cast<double>(count));
  std::vector<Vec2> pts = jitteredCells(rect, c, rng);  // ceil(W/c)·ceil(H/c) ≥ count cells
  for (Index k = static_cast<Index>(pts.size()); k > count; --k) {
    const auto victim = static_cast<std::size_t>(rng() % static_cast<std::uint64_t>(k));
    pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(victim));
  }
  Points X = toPoints(pts);
  relax.spacing = h;
  RelaxRegion region;
  region.domain = rect;
  region.periodic = true;
  const InverseMeanShiftReport r = relaxInverseMeanShift(X, 0, region, relax);
  if (report) *report = r;
  return X;
}

}  // namespace kc::sampling
