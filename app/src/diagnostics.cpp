#include "kc/app/diagnostics.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "kc/app/backend.h"

namespace kc::app {
namespace {

PropertyRow measure(const Weights& W, const Points& C, const Points& P) {
  PropertyRow r;
  r.points = P.rows();
  if (P.rows() == 0) return r;
  r.partitionOfUnity = partitionOfUnityError(W);
  r.reproduction = reproductionError(W, C, P);
  r.minWeight = minWeight(W);
  r.negatives = negativeCount(W);
  return r;
}

Points selectRows(const Points& P, const std::vector<Index>& rows) {
  Points Q(static_cast<Index>(rows.size()), 2);
  for (std::size_t k = 0; k < rows.size(); ++k) Q.row(static_cast<Index>(k)) = P.row(rows[k]);
  return Q;
}

Weights selectRows(const Weights& W, const std::vector<Index>& rows) {
  Weights Q(static_cast<Index>(rows.size()), W.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) Q.row(static_cast<Index>(k)) = W.row(rows[k]);
  return Q;
}

}  // namespace

DragArea dragArea(const Weights& W, int step) {
  DragArea a;
  a.step = step;
  a.points = W.rows();
  const Index m = W.cols();
  a.fraction.assign(static_cast<std::size_t>(m), 0.0);
  if (W.rows() == 0 || m == 0) return a;
  for (Index i = 0; i < m; ++i) {
    const double f = static_cast<double>((W.col(i).array() >= kDragWeight).count()) / static_cast<double>(W.rows());
    a.fraction[static_cast<std::size_t>(i)] = f;
    a.mean += f / static_cast<double>(m);
    if (f > a.max || a.maxControl < 0) {
      a.max = f;
      a.maxControl = i;
    }
  }
  a.minWeight = W.minCoeff();
  return a;
}

Diagnostics diagnose(const Session& s, Index maxPoints) {
  if (!s.hasField()) throw std::invalid_argument("the session has no coordinate field (bind it first)");
  const auto t0 = std::chrono::steady_clock::now();
  Diagnostics d;
  const Points& C = s.cage.C;
  d.samples = measure(s.W, C, s.samples.X);

  // Pixel centres over the image on a step chosen to keep the count near maxPoints.
  const double area = static_cast<double>(s.imageWidth) * s.imageHeight;
  d.pixelStep = std::max(1, static_cast<int>(std::ceil(std::sqrt(area / static_cast<double>(std::max<Index>(1, maxPoints))))));
  const int nx = (s.imageWidth + d.pixelStep - 1) / d.pixelStep, ny = (s.imageHeight + d.pixelStep - 1) / d.pixelStep;
  Points P(static_cast<Index>(nx) * ny, 2);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) P.row(static_cast<Index>(y) * nx + x) << (x * d.pixelStep + 0.5), (y * d.pixelStep + 0.5);
  const Weights W = s.field->weightsAt(P);
  d.outsideWeights = sessionCapabilities(s).outsideCage;
  if (d.outsideWeights) d.image = measure(W, C, P);

  std::vector<Index> inside;
  const CageQueries cage(s.cage);
  for (Index i = 0; i < P.rows(); ++i)
    if (cage.inside(P.row(i).transpose())) inside.push_back(i);
  const Weights Win = selectRows(W, inside);
  d.inside = measure(Win, C, selectRows(P, inside));

  d.lagrange = lagrangeError(s.field->weightsAt(C));

  // Points strictly inside every cage edge, every h/8 (at least 16 per edge): the field between
  // the edge samples, not only at them. Edges off the loops (sticks) are measured on their own too.
  const double step = (s.params.spacing > 0.0 ? s.params.spacing : 1.0) / 8.0;
  const auto edges = cageEdges(s.cage);
  const std::vector<char> onLoop = loopEdgeFlags(s.cage);
  for (const bool sticks : {false, true}) {
    std::vector<std::array<int, 2>> ends;
    std::vector<Vec2> along;
    for (std::size_t e = 0; e < edges.size(); ++e) {
      if (sticks && onLoop[e]) continue;
      const auto [a, b] = edges[e];
      const int n = std::max(16, static_cast<int>(std::ceil((C.row(b) - C.row(a)).norm() / step)));
      for (int t = 1; t <= n; ++t) {
        const double u = t / (n + 1.0);
        along.push_back((1 - u) * C.row(a).transpose() + u * C.row(b).transpose());
        ends.push_back({a, b});
      }
    }
    if (along.empty()) continue;
    Points E(static_cast<Index>(along.size()), 2);
    for (std::size_t k = 0; k < along.size(); ++k) E.row(static_cast<Index>(k)) = along[k].transpose();
    (sticks ? d.stickLinearity : d.edgeLinearity) = edgeLinearityError(s.field->weightsAt(E), C, E, ends);
    d.sticks = sticks;
  }

  if (!inside.empty()) {
    const Eigen::VectorXd pixelArea = Eigen::VectorXd::Constant(static_cast<Index>(inside.size()), 1.0);
    d.locality = localityStats(Win, pixelArea, {1e-4, 1e-3, 1e-2, 1e-1});
    // Unit areas: meanInfluencing is the mean count of entries above 10⁻³/m per point.
    d.compactFraction = (12.0 * d.locality.meanInfluencing + 4.0) / (8.0 * static_cast<double>(std::max<Index>(1, C.rows())));
  }
  // The drag area on every `every`-th point of the grid, at least 2 px apart.
  const int every = d.pixelStep >= 2 ? 1 : 2;
  std::vector<Index> coarse;
  for (std::size_t k = 0; k < inside.size(); ++k)
    if ((inside[k] % nx) % every == 0 && (inside[k] / nx) % every == 0) coarse.push_back(static_cast<Index>(k));
  d.drag = dragArea(every == 1 ? Win : selectRows(Win, coarse), every * d.pixelStep);
  d.evalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

}  // namespace kc::app
