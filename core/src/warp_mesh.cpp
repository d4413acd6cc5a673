#include "kc/core/warp_mesh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>

#include "kc/core/cage_conforming_grid.h"
#include "kc/core/parallel.h"
#include "kc/core/timing.h"
#include "triangle_area.h"

namespace kc {
namespace {

using Clock = std::chrono::steady_clock;

/// DeformPass::Live: the fold repair's work budget (ExteriorRepairOptions::budget; Final: 4). A
/// quarter of the Final pass's, so a pose that is hard to untangle costs less per frame; folds it
/// leaves show until the release.
const double kLiveRepairBudget = 1.0;
/// DeformPass::Live: relaxation sweeps per frame (ExteriorRepairOptions::relaxSweeps; Final: 300).
/// While dragging, each frame starts from the last relaxed picture, so the sweeps add up.
const int kLiveRelaxSweeps = 20;


using detail::signedArea2;

}  // namespace

std::vector<double> gridAxis(int n, double spacing) {
  const int cells = std::max(1, static_cast<int>(std::ceil(n / spacing - 1e-9)));
  std::vector<double> axis(static_cast<std::size_t>(cells) + 1);
  for (int k = 0; k <= cells; ++k) axis[std::size_t(k)] = -0.5 + double(n) * k / cells;
  return axis;
}

double automaticMeshSpacing(int width, int height, double fieldSpacing) {
  const double picture = std::sqrt(std::max(0.0, double(width)) * std::max(0.0, double(height)) / kAutoMeshVertices);
  const double field = std::isfinite(fieldSpacing) && fieldSpacing > 0.0 ? kAutoMeshPerFieldSpacing * fieldSpacing : 0.0;
  return std::max({kMinAutoMeshSpacing, field, picture});
}

WarpMesh::WarpMesh(int width, int height, const Cage& cage, const WarpMeshOptions& options)
    : m_width(width), m_height(height), m_options(options), m_cage(cage) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("warp mesh: image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is empty");
  if (!(options.spacing >= 0.5) || !std::isfinite(options.spacing))
    throw std::invalid_argument("warp mesh: spacing must be at least 0.5 pixels");
  if (!(options.keepThreshold >= 0.0) || !(options.keepThreshold < 1.0))
    throw std::invalid_argument("warp mesh: keep threshold must be in [0, 1)");
  validateCage(cage);
  const bool cull = options.outside == OutsideMode::Fixed || options.outside == OutsideMode::Transparent;
  if (cull && !hasInterior(cage))
    throw std::invalid_argument("warp mesh: outside mode '" + std::string(toString(options.outside)) +
                                "' needs a cage with an inside (a closed loop)");

  const std::vector<double> xs = gridAxis(width, options.spacing), ys = gridAxis(height, options.spacing);
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size());
  const auto vid = [nx](int i, int j) { return j * nx + i; };

  if (options.outside == OutsideMode::Pinned && options.followCage) {
    buildPinned(xs, ys);
    return;
  }
  if (cull && options.followCage) {
    buildInside(xs, ys);
    return;
  }
  // Which grid vertices can touch the cage region (only needed when culling).
  std::vector<std::uint8_t> near(std::size_t(nx) * ny, 1);
  if (cull) {
    const double reach = 1.5 * std::hypot(xs[1] - xs[0], ys[1] - ys[0]);
    const CageQueries queries(cage);
    parallelFor(Index(nx) * ny, [&](Index v) {
      const Vec2 p(xs[std::size_t(v % nx)], ys[std::size_t(v / nx)]);
      near[std::size_t(v)] = (queries.inside(p) || queries.distance(p) <= reach) ? 1 : 0;
    }, 512);
  }
  // Two triangles per cell, row-major cell order (this order decides fold-over overlaps).
  Triangles all;
  all.reserve(std::size_t(nx - 1) * (ny - 1) * 2);
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = vid(i, j), b = vid(i + 1, j), c = vid(i, j + 1), d = vid(i + 1, j + 1);
      for (const std::array<int, 3>& t : {std::array<int, 3>{a, b, d}, std::array<int, 3>{a, d, c}})
        if (near[std::size_t(t[0])] || near[std::size_t(t[1])] || near[std::size_t(t[2])]) all.push_back(t);
    }
  // Keep only vertices used by a kept triangle, renumbered in grid order.
  std::vector<int> newId(std::size_t(nx) * ny, -1);
  for (const auto& t : all)
    for (int k : t) newId[std::size_t(k)] = 0;
  int count = 0;
  for (auto& id : newId)
    if (id == 0) id = count++;
  m_rest.resize(count, 2);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if (const int id = newId[std::size_t(vid(i, j))]; id >= 0) m_rest.row(id) << xs[std::size_t(i)], ys[std::size_t(j)];
  m_triangles.resize(all.size());
  m_restArea.resize(Index(all.size()));
  for (std::size_t t = 0; t < all.size(); ++t) {
    for (int k = 0; k < 3; ++k) m_triangles[t][std::size_t(k)] = newId[std::size_t(all[t][std::size_t(k)])];
    m_restArea(Index(t)) = 0.5 * signedArea2(m_rest, m_triangles[t]);
  }
  m_deformed = m_rest;
  m_jacobian = Eigen::VectorXd::Ones(Index(m_triangles.size()));
  if (options.outside == OutsideMode::Pinned) {  // no culling: vertex ids are grid ids
    ExteriorWeightsOptions eo;
    eo.keepThreshold = options.keepThreshold;
    eo.stickBand = options.stickBand;
    m_exterior = std::make_shared<const ExteriorWeights>(pinnedExteriorWeights(xs, ys, cage, eo));
    // The picture inside the cage is drawn over its stretched background: triangles wholly
    // outside the cage first, then those across the cage, then the inside (the rasterizer
    // composites in index order, later on top).
    const auto insideCount = [&](const std::array<int, 3>& t) {
      return int(!m_exterior->exterior[std::size_t(t[0])]) + int(!m_exterior->exterior[std::size_t(t[1])]) +
             int(!m_exterior->exterior[std::size_t(t[2])]);
    };
    const auto layer = [&](const std::array<int, 3>& t) { const int k = insideCount(t); return k == 0 ? 0 : (k == 3 ? 2 : 1); };
    std::stable_sort(m_triangles.begin(), m_triangles.end(), [&](const auto& a, const auto& b) { return layer(a) < layer(b); });
    m_outsideTriangles = Index(std::count_if(m_triangles.begin(), m_triangles.end(), [&](const auto& t) { return layer(t) == 0; }));
    buildRepair(xs, ys);
    buildFade();
    for (std::size_t t = 0; t < m_triangles.size(); ++t) m_restArea(Index(t)) = 0.5 * signedArea2(m_rest, m_triangles[t]);
  }
}

void WarpMesh::buildPinned(const std::vector<double>& xs, const std::vector<double>& ys) {
  ExteriorWeightsOptions eo;
  eo.keepThreshold = m_options.keepThreshold;
  eo.stickBand = m_options.stickBand;
  ExteriorWeights ext = pinnedExteriorWeights(xs, ys, m_cage, eo);
  // The mesh follows the cage: every triangle lies wholly outside (drawn first) or wholly inside
  // (drawn over its stretched background; a stick band counts as inside).
  CageConformingGrid grid = cageConformingGrid(xs, ys, m_cage, ext.exterior, ext.band);
  m_rest = std::move(grid.V);
  m_triangles = std::move(grid.T);
  m_outsideTriangles = grid.outsideTriangles;
  const Index nv = m_rest.rows();
  // Points on the cage take the field's weights (they belong to the inside's triangles too).
  ext.exterior.resize(std::size_t(nv), 0);
  if (!ext.band.empty()) ext.band.resize(std::size_t(nv), 0);
  ext.H.conservativeResize(nv, ext.H.cols());
  m_exterior = std::make_shared<const ExteriorWeights>(std::move(ext));
  buildRepair(xs, ys);
  buildFade();
  m_restArea.resize(Index(m_triangles.size()));
  for (std::size_t t = 0; t < m_triangles.size(); ++t) m_restArea(Index(t)) = 0.5 * signedArea2(m_rest, m_triangles[t]);
  m_deformed = m_rest;
  m_jacobian = Eigen::VectorXd::Ones(Index(m_triangles.size()));
}

void WarpMesh::buildInside(const std::vector<double>& xs, const std::vector<double>& ys) {
  const int nx = int(xs.size()), ny = int(ys.size());
  const CageQueries queries(m_cage);
  std::vector<std::uint8_t> exterior(std::size_t(nx) * ny, 0);
  parallelFor(Index(nx) * ny, [&](Index v) {
    exterior[std::size_t(v)] = queries.inside(Vec2(xs[std::size_t(v % nx)], ys[std::size_t(v / nx)])) ? 0 : 1;
  }, 512);
  const CageConformingGrid grid = cageConformingGrid(xs, ys, m_cage, exterior);
  // The inside's triangles, and only the vertices they use (renumbered in the grid's order).
  std::vector<int> newId(std::size_t(grid.V.rows()), -1);
  for (std::size_t t = std::size_t(grid.outsideTriangles); t < grid.T.size(); ++t)
    for (int k : grid.T[t]) newId[std::size_t(k)] = 0;
  int count = 0;
  for (auto& id : newId)
    if (id == 0) id = count++;
  m_rest.resize(count, 2);
  for (Index v = 0; v < grid.V.rows(); ++v)
    if (const int id = newId[std::size_t(v)]; id >= 0) m_rest.row(id) = grid.V.row(v);
  m_triangles.clear();
  for (std::size_t t = std::size_t(grid.outsideTriangles); t < grid.T.size(); ++t)
    m_triangles.push_back({newId[std::size_t(grid.T[t][0])], newId[std::size_t(grid.T[t][1])], newId[std::size_t(grid.T[t][2])]});
  m_restArea.resize(Index(m_triangles.size()));
  for (std::size_t t = 0; t < m_triangles.size(); ++t) m_restArea(Index(t)) = 0.5 * signedArea2(m_rest, m_triangles[t]);
  m_deformed = m_rest;
  m_jacobian = Eigen::VectorXd::Ones(Index(m_triangles.size()));
}

void WarpMesh::buildRepair(const std::vector<double>& xs, const std::vector<double>& ys) {
  if (!m_options.repairFolds) return;
  // Movable: vertices strictly outside the cage; on the image border, all but the corners may
  // slide along it or move outward where the repair needs it (exterior_untangle.h).
  const Index nv = m_rest.rows();
  std::vector<std::uint8_t> movable(std::size_t(nv), 0);
  for (Index v = 0; v < nv; ++v) movable[std::size_t(v)] = m_exterior->exterior[std::size_t(v)] ? 1 : 0;
  const ExteriorRepairFrame frame{xs.front(), ys.front(), xs.back(), ys.back()};
  m_repair = std::make_shared<const ExteriorRepairTopology>(exteriorRepairTopology(m_rest, m_triangles, m_outsideTriangles, movable, &frame));
}

void WarpMesh::buildFade() {
  if (!(m_options.fadeBand > 0.0)) return;
  const Index nv = m_rest.rows();
  const auto exterior = [this](Index v) { return m_exterior->exterior[std::size_t(v)] != 0; };
  // Vertex neighbours (CSR) over the drawn triangles.
  std::vector<int> start(std::size_t(nv) + 1, 0), items;
  for (const auto& t : m_triangles)
    for (int k : t) start[std::size_t(k) + 1] += 2;
  for (Index v = 0; v < nv; ++v) start[std::size_t(v) + 1] += start[std::size_t(v)];
  items.resize(std::size_t(start.back()));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const auto& t : m_triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[std::size_t(k)];
      items[std::size_t(fill[std::size_t(a)]++)] = t[std::size_t((k + 1) % 3)];
      items[std::size_t(fill[std::size_t(a)]++)] = t[std::size_t((k + 2) % 3)];
    }
  // Distances from the edge of the outside by nearest-source propagation (each vertex keeps the
  // edge vertex it is nearest to, as a vector distance transform does): a Dijkstra order over the
  // exterior vertices, the distance to a source measured straight, not along mesh edges.
  auto fade = std::make_shared<Fade>();
  fade->distance.assign(std::size_t(nv), std::numeric_limits<double>::infinity());
  std::vector<Index> source(std::size_t(nv), -1);
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (Index v = 0; v < nv; ++v) {
    if (exterior(v)) continue;
    fade->distance[std::size_t(v)] = 0.0;
    const auto first = items.begin() + start[std::size_t(v)], last = items.begin() + start[std::size_t(v) + 1];
    if (std::any_of(first, last, [&](int u) { return exterior(u); })) {
      fade->edge.push_back(v);
      source[std::size_t(v)] = v;
      queue.push({0.0, v});
    }
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > fade->distance[std::size_t(v)]) continue;
    const Vec2 s = m_rest.row(source[std::size_t(v)]);
    for (int k = start[std::size_t(v)]; k < start[std::size_t(v) + 1]; ++k) {
      const int u = items[std::size_t(k)];
      if (!exterior(u)) continue;
      const double du = (Vec2(m_rest.row(u)) - s).norm();
      if (du < fade->distance[std::size_t(u)]) {
        fade->distance[std::size_t(u)] = du;
        source[std::size_t(u)] = source[std::size_t(v)];
        queue.push({du, u});
      }
    }
  }
  // Vertices no triangle uses (grid vertices next to the cage, cage_conforming_grid.h) or that no
  // path reaches: their straight distance to the cage (they are drawn by no triangle).
  const CageQueries queries(m_cage);
  parallelFor(nv, [&](Index v) {
    double& d = fade->distance[std::size_t(v)];
    if (!std::isfinite(d)) d = queries.distance(m_rest.row(v));
  }, 256);
  m_fade = std::move(fade);
}

double WarpMesh::fadeExterior() {
  double D = 0.0;
  for (const Index v : m_fade->edge) D = std::max(D, (m_deformed.row(v) - m_rest.row(v)).norm());
  if (!(D > 0.0)) return 0.0;
  const double B = m_options.fadeBand * D;
  const std::vector<double>& r = m_fade->distance;
  parallelFor(m_rest.rows(), [&](Index v) {
    if (!m_exterior->exterior[std::size_t(v)]) return;
    const double t = r[std::size_t(v)] / B;
    const double phi = t < 1.0 ? 1.0 - t * t * (3.0 - 2.0 * t) : 0.0;
    m_deformed.row(v) = m_rest.row(v) + phi * (m_deformed.row(v) - m_rest.row(v));
  }, 4096);
  return B;
}

CompactWeightsReport WarpMesh::setWeights(const Weights& W) {
  const auto t0 = Clock::now();
  const Index nv = m_rest.rows(), m = W.cols();
  if (W.rows() != nv)
    throw std::invalid_argument("warp mesh: weights have " + std::to_string(W.rows()) + " rows but the mesh has " +
                                std::to_string(nv) + " vertices");
  if (m != m_cage.size())
    throw std::invalid_argument("warp mesh: weights have " + std::to_string(m) + " columns but the cage has " +
                                std::to_string(m_cage.size()) + " control points");
  if (!W.allFinite()) throw std::invalid_argument("warp mesh: weights contain NaN or infinity");
  const double keep = m_options.keepThreshold / double(m);
  m_previousFoldFree = false;  // a live repair starts from a picture of these weights only
  // Pinned mode: rows of exterior vertices come from the harmonic extension (with the anchor);
  // with a stick band, its data are these weights at the band's edge (solved again here).
  if (m_exterior && m_exterior->needsFieldData()) {
    auto ext = std::make_shared<ExteriorWeights>(*m_exterior);
    setFieldData(*ext, W);
    m_exterior = std::move(ext);
  }
  const ExteriorWeights* ext = m_exterior.get();
  const auto exterior = [ext](Index v) { return ext && ext->exterior[std::size_t(v)]; };

  // Pass 1: entries kept per row (the row's largest entry is always kept).
  std::vector<int> rowCount(std::size_t(nv), 0);
  std::vector<double> dropped(std::size_t(nv), 0.0);
  parallelFor(nv, [&](Index v) {
    if (exterior(v)) {
      rowCount[std::size_t(v)] = int(ext->H.outerIndexPtr()[v + 1] - ext->H.outerIndexPtr()[v]);
      return;
    }
    int n = 0;
    Index best = 0;
    double mass = 0.0, sum = 0.0;
    for (Index i = 0; i < m; ++i) {
      if (std::abs(W(v, i)) > keep) ++n, sum += W(v, i);
      else mass += std::abs(W(v, i));
      if (W(v, i) > W(v, best)) best = i;
    }
    if (n == 0 || !(sum > 0.0)) {  // nothing usable: the largest weight takes it all
      n = 1;
      mass = W.row(v).cwiseAbs().sum() - std::abs(W(v, best));
    }
    rowCount[std::size_t(v)] = n;
    dropped[std::size_t(v)] = mass;
  }, 1024);
  m_weights = SparseWeights(nv, ext ? m + 1 : m);
  int* outer = m_weights.outerIndexPtr();
  outer[0] = 0;
  for (Index v = 0; v < nv; ++v) outer[v + 1] = outer[v] + rowCount[std::size_t(v)];
  m_weights.resizeNonZeros(outer[nv]);
  double* values = m_weights.valuePtr();
  int* cols = m_weights.innerIndexPtr();
  // Pass 2: fill and renormalize to partition of unity.
  parallelFor(nv, [&](Index v) {
    int k = outer[v];
    if (exterior(v)) {
      for (CompactWeights::InnerIterator it(ext->H, v); it; ++it, ++k) {
        cols[k] = int(it.col());
        values[k] = it.value();
      }
      return;
    }
    double sum = 0.0;
    for (Index i = 0; i < m; ++i)
      if (std::abs(W(v, i)) > keep) {
        cols[k] = static_cast<int>(i);
        values[k] = W(v, i);
        sum += W(v, i);
        ++k;
      }
    if (k == outer[v] || !(sum > 0.0)) {  // nothing usable: the largest weight takes it all
      k = outer[v];
      Index best = 0;
      for (Index i = 1; i < m; ++i)
        if (W(v, i) > W(v, best)) best = i;
      cols[k] = static_cast<int>(best);
      values[k] = 1.0;
      sum = 1.0;
      ++k;
    }
    for (int q = outer[v]; q < k; ++q) values[q] /= sum;
  }, 1024);

  CompactWeightsReport rep;
  rep.vertices = nv;
  rep.controls = m;
  rep.nonZeros = outer[nv];
  rep.meanPerVertex = nv > 0 ? double(rep.nonZeros) / double(nv) : 0.0;
  for (Index v = 0; v < nv; ++v) {
    rep.maxPerVertex = std::max<Index>(rep.maxPerVertex, rowCount[std::size_t(v)]);
    rep.droppedMass = std::max(rep.droppedMass, dropped[std::size_t(v)]);
  }
  rep.compactBytes = std::size_t(rep.nonZeros) * (sizeof(double) + sizeof(int)) + std::size_t(nv + 1) * sizeof(int);
  rep.denseBytes = std::size_t(nv) * std::size_t(m) * sizeof(double);
  rep.seconds = secondsSince(t0);
  return rep;
}

CompactWeightsReport WarpMesh::setWeights(const SparseWeights& W) { return setWeights(Weights(W)); }

DeformReport WarpMesh::deform(const Pose& pose, DeformPass pass) {
  const auto t0 = Clock::now();
  if (!hasWeights()) throw std::invalid_argument("warp mesh: deform() called before setWeights()");
  const std::vector<Affine2> T = handleTransforms(m_cage.C, pose);
  const Index nv = m_rest.rows();
  const int* outer = m_weights.outerIndexPtr();
  const int* cols = m_weights.innerIndexPtr();
  const double* values = m_weights.valuePtr();
  // Every T_i is [R(θ_i) | d_i] with R = [[cos, sin], [−sin, cos]], so Σ_i w_i T_i needs only four
  // sums: Σ w cos θ, Σ w sin θ and Σ w d (3.38). Packed per control for the inner loop.
  // In Pinned mode the last column is the anchor: the identity.
  std::vector<std::array<double, 4>> packed(std::size_t(m_weights.cols()), {1.0, 0.0, 0.0, 0.0});
  for (std::size_t i = 0; i < T.size(); ++i) packed[i] = {T[i](0, 0), T[i](0, 1), T[i](0, 2), T[i](1, 2)};
  // f(v) = (Σ_i w_i T_i) [v; 1]  (3.37)
  parallelForRange(nv, 4096, [&](Index begin, Index end) {
    for (Index v = begin; v < end; ++v) {
      double c = 0, s = 0, dx = 0, dy = 0;
      for (int k = outer[v]; k < outer[v + 1]; ++k) {
        const std::array<double, 4>& p = packed[std::size_t(cols[k])];
        const double w = values[k];
        c += w * p[0];
        s += w * p[1];
        dx += w * p[2];
        dy += w * p[3];
      }
      const double x = m_rest(v, 0), y = m_rest(v, 1);
      m_deformed(v, 0) = c * x + s * y + dx;
      m_deformed(v, 1) = -s * x + c * y + dy;
    }
  });
  DeformReport rep;
  if (m_fade) rep.fadeWidth = fadeExterior();
  if (m_repair) {
    const auto t1 = Clock::now();
    // While dragging, the continuation starts from the last picture when that one was fold-free.
    const bool warm = pass == DeformPass::Live && m_previousFoldFree && m_previous.rows() == nv;
    ExteriorRepairOptions options;
    if (pass == DeformPass::Live) {
      options.budget = kLiveRepairBudget;
      options.relaxSweeps = kLiveRelaxSweeps;
    }
    const Points harmonic = warm ? m_deformed : Points();
    ExteriorRepairReport r = repairExteriorFolds(m_rest, m_deformed, m_triangles, *m_repair, m_outsideTriangles, m_restArea, options,
                                                 warm ? ExteriorRepairStart{&m_previous} : ExteriorRepairStart{});
    if (warm && r.foldedAfter > r.foldedForced) {  // the short continuation did not untangle it: from rest
      m_deformed = harmonic;
      r = repairExteriorFolds(m_rest, m_deformed, m_triangles, *m_repair, m_outsideTriangles, m_restArea, options);
    }
    rep.harmonicFolds = r.foldedBefore;
    rep.repairedFolds = r.foldedAfter;
    rep.repairVertices = r.regionVertices;
    rep.repairBorderVertices = r.borderVertices;
    rep.repairWarmStart = r.warmStart;
    rep.repairSeconds = secondsSince(t1);
    m_previousFoldFree = r.foldedAfter == r.foldedForced;                            // (folds the inside forces stay in any case)
    if (pass == DeformPass::Live || m_previous.rows() > 0) m_previous = m_deformed;  // (kept once a live pass asked for it)
  }
  const Index nt = Index(m_triangles.size());
  parallelForRange(nt, 8192, [&](Index begin, Index end) {
    for (Index t = begin; t < end; ++t)
      m_jacobian(t) = 0.5 * signedArea2(m_deformed, m_triangles[std::size_t(t)]) / m_restArea(t);
  });
  rep.minJacobian = nt > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  rep.maxJacobian = nt > 0 ? -std::numeric_limits<double>::infinity() : 0.0;
  for (Index t = 0; t < nt; ++t) {
    const double j = m_jacobian(t);
    rep.minJacobian = std::min(rep.minJacobian, j);
    rep.maxJacobian = std::max(rep.maxJacobian, j);
    if (!(j > 0.0)) {
      ++rep.flippedTriangles;
      rep.flippedArea += std::abs(m_restArea(t));
    }
  }
  rep.seconds = secondsSince(t0);
  return rep;
}

Image WarpMesh::render(const Image& source, const RasterOptions& options, RasterReport* report) const {
  source.validate();
  if (source.width != m_width || source.height != m_height)
    throw std::invalid_argument("warp mesh: source image is " + std::to_string(source.width) + "x" +
                                std::to_string(source.height) + " but the mesh was built for " +
                                std::to_string(m_width) + "x" + std::to_string(m_height));
  switch (m_options.outside) {
    case OutsideMode::Pinned:
    case OutsideMode::Deform:
      return rasterizeMesh(source, m_rest, m_deformed, m_triangles, m_width, m_height, options, report);
    case OutsideMode::Transparent: {
      const Image inside = applyMask(source, cageMask(m_cage, m_width, m_height));
      return rasterizeMesh(inside, m_rest, m_deformed, m_triangles, m_width, m_height, options, report);
    }
    case OutsideMode::Fixed: {
      const Image inside = applyMask(source, cageMask(m_cage, m_width, m_height));
      Image out = source;
      rasterizeMeshInto(out, inside, m_rest, m_deformed, m_triangles, options, report);
      return out;
    }
  }
  return {};
}

}  // namespace kc
