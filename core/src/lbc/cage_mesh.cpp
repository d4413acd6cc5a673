// The one translation unit that includes CGAL (its headers are slow to compile): the LBC
// domain mesh. CGAL's 2D constrained Delaunay triangulation + Delaunay mesher.
#include "kc/core/lbc/cage_mesh.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace kc {
namespace {

/// What we know about a vertex we inserted: a control (id) or an edge point (edge e, parameter t).
struct VertexInfo {
  int control = -1;
  int edge = -1;
  double t = 0.0;
};

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K, CGAL::Delaunay_mesh_vertex_base_2<K>>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;

/// CGAL's size and angle criteria with a local size bound: a triangle is imperatively bad while
/// its longest edge exceeds min(spacing, h(centroid)) and bad while the squared sine of its
/// smallest angle is below the angle bound B (the quality measures of
/// Delaunay_mesh_size_criteria_2, with the size normalized by the local bound).
class GradedCriteria : public Criteria {
 public:
  GradedCriteria(double angleBound, double spacing, const SizingField& h)
      : CGAL::Delaunay_mesh_criteria_2<Cdt>(angleBound), Criteria(angleBound, spacing), m_h(&h) {}

  class Is_bad {
   public:
    Is_bad(double angleBound, double spacing, const SizingField* h) : m_b(angleBound), m_spacing(spacing), m_h(h) {}

    CGAL::Mesh_2::Face_badness operator()(const Quality q) const {
      if (q.size() > 1) return CGAL::Mesh_2::IMPERATIVELY_BAD;
      return q.sine() < m_b ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }

    CGAL::Mesh_2::Face_badness operator()(const Cdt::Face_handle& f, Quality& q) const {
      const Vec2 a(f->vertex(0)->point().x(), f->vertex(0)->point().y());
      const Vec2 b(f->vertex(1)->point().x(), f->vertex(1)->point().y());
      const Vec2 c(f->vertex(2)->point().x(), f->vertex(2)->point().y());
      std::array<double, 3> sq = {(b - c).squaredNorm(), (c - a).squaredNorm(), (a - b).squaredNorm()};
      std::sort(sq.begin(), sq.end());
      const double local = std::min(m_spacing, (*m_h)((a + b + c) / 3.0));
      q.second = sq[2] / (local * local);
      if (q.size() > 1) {
        q.first = 1.0;  // the sine is not needed
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      }
      const double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      q.first = area2 * area2 / (sq[2] * sq[1]);
      return q.sine() < m_b ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }

   private:
    double m_b, m_spacing;
    const SizingField* m_h;
  };

  Is_bad is_bad_object() const { return Is_bad(bound(), size_bound(), m_h); }

 private:
  const SizingField* m_h;
};

/// Delaunay refinement of `cdt` by `criteria`, step by step; false (and stopped) when the mesh
/// would pass `maxVertices`.
template <class Crit>
bool refine(Cdt& cdt, const Crit& criteria, Index maxVertices) {
  CGAL::Delaunay_mesher_2<Cdt, Crit> mesher(cdt, criteria);
  mesher.init();
  while (!mesher.is_refinement_done()) {
    if (Index(cdt.number_of_vertices()) > maxVertices) return false;
    mesher.step_by_step_refine_mesh();
  }
  return true;
}

// The plain constrained triangulation of constrainedTriangulation(): vertices carry their row.
using PlainVb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using PlainFb = CGAL::Constrained_triangulation_face_base_2<K>;
using PlainCdt = CGAL::Constrained_Delaunay_triangulation_2<K, CGAL::Triangulation_data_structure_2<PlainVb, PlainFb>,
                                                            CGAL::Exact_predicates_tag>;

/// The closed polygon's edges; throws unless the cage is a closed polygon.
std::vector<std::array<int, 2>> polygonEdges(const Cage& cage) {
  if (!cage.closed) throw std::invalid_argument("LBC needs a closed cage (an open cage has no interior to mesh)");
  if (!isClosedPolygon(cage))
    throw std::invalid_argument("LBC needs the cage to be one closed polygon through its points in order "
                                "(this cage lists its own edges)");
  return cageEdges(cage);
}

/// Vertices per h² of area of a Delaunay-refined mesh with edges ≤ h and angles ≥ 20° (measured:
/// checker 2.50, figure 2.47, star 2.43 at h = 6 px, after the cage's edge points perimeter / h).
constexpr double kVerticesPerSquareSpacing = 2.45;

/// Morton (Z-order) code of p in the box [lo, lo + extent]²: 16 bits per axis, interleaved.
std::uint32_t mortonCode(double x, double y, const Vec2& lo, double extent) {
  auto spread = [](std::uint32_t v) {
    v &= 0xffff;
    v = (v | (v << 8)) & 0x00ff00ff;
    v = (v | (v << 4)) & 0x0f0f0f0f;
    v = (v | (v << 2)) & 0x33333333;
    return (v | (v << 1)) & 0x55555555;
  };
  const double q = 65535.0 / extent;
  return spread(std::uint32_t(std::clamp((x - lo.x()) * q, 0.0, 65535.0))) |
         (spread(std::uint32_t(std::clamp((y - lo.y()) * q, 0.0, 65535.0))) << 1);
}

}  // namespace

CageMesh meshCageInterior(const Cage& cage, const CageMeshOptions& options) {
  if (!(options.spacing > 0.0) || !std::isfinite(options.spacing))
    throw std::invalid_argument("LBC mesh: the spacing must be positive and finite");
  validateCage(cage);
  const auto edges = polygonEdges(cage);
  const Index m = cage.size();
  const Points& C = cage.C;

  // Controls and pre-split edge points, each with what it is; then the constraints between them.
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> control(static_cast<std::size_t>(m));
  for (Index i = 0; i < m; ++i) {
    control[std::size_t(i)] = cdt.insert(Cdt::Point(C(i, 0), C(i, 1)));
    control[std::size_t(i)]->info().control = int(i);
  }
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [k, l] = edges[e];
    const Vec2 a = C.row(k), b = C.row(l);
    std::vector<double> division;  // t_0 = 0 < t_1 < … < t_n = 1
    if (options.sizing) {
      division = segmentDivision(a, b, *options.sizing);
    } else {
      const int pieces = std::max(1, int(std::ceil((b - a).norm() / options.spacing - 1e-9)));
      for (int p = 0; p <= pieces; ++p) division.push_back(double(p) / pieces);
    }
    const std::size_t pieces = division.size() - 1;
    Cdt::Vertex_handle prev = control[std::size_t(k)];
    for (std::size_t p = 1; p <= pieces; ++p) {
      Cdt::Vertex_handle next = control[std::size_t(l)];
      if (p < pieces) {
        const double t = division[p];
        const Vec2 x = (1.0 - t) * a + t * b;
        next = cdt.insert(Cdt::Point(x.x(), x.y()));
        next->info().edge = int(e);
        next->info().t = t;
      }
      cdt.insert_constraint(prev, next);
      prev = next;
    }
  }

  // Refinement, step by step so a spacing far too small for the cage stops at maxVertices.
  const double angle = std::clamp(options.minAngleDegrees, 0.0, 20.7) * std::numbers::pi / 180.0;
  const double bound = std::sin(angle) * std::sin(angle);
  CageMesh out;
  out.controls = m;
  if (!(options.sizing ? refine(cdt, GradedCriteria(bound, options.spacing, *options.sizing), options.maxVertices)
                       : refine(cdt, Criteria(bound, options.spacing), options.maxVertices))) {
    out.status = SolveStatus::TooLarge;
    return out;
  }

  // Points the mesher put on the cage: on a constrained edge, with no info. Their cage edge is
  // the nearest one; they are moved exactly onto it.
  std::vector<Cdt::Vertex_handle> onEdge, inside;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    if (v->info().control >= 0) continue;
    if (v->info().edge >= 0) {
      onEdge.push_back(v);
      continue;
    }
    bool constrained = false;
    auto e = cdt.incident_edges(v), done = e;
    do constrained = constrained || (!cdt.is_infinite(e) && cdt.is_constrained(*e));
    while (++e != done && !constrained);
    if (constrained) {
      const Vec2 p(v->point().x(), v->point().y());
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < edges.size(); ++k) {
        const double d = pointSegmentDistance(p, C.row(edges[k][0]), C.row(edges[k][1]));
        if (d < best) {
          best = d;
          v->info().edge = int(k);
        }
      }
      const Vec2 a = C.row(edges[std::size_t(v->info().edge)][0]), b = C.row(edges[std::size_t(v->info().edge)][1]);
      v->info().t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      onEdge.push_back(v);
    } else {
      inside.push_back(v);
    }
  }

  // Numbering: controls, edge points (by edge, then t), interior points in Z-order so that the
  // solvers' per-vertex and per-triangle loops touch memory locally.
  const Vec2 lo = C.colwise().minCoeff();
  const double extent = std::max((C.colwise().maxCoeff() - C.colwise().minCoeff()).maxCoeff(), 1e-300);
  std::sort(onEdge.begin(), onEdge.end(), [](const auto& a, const auto& b) {
    return std::pair(a->info().edge, a->info().t) < std::pair(b->info().edge, b->info().t);
  });
  auto morton = [&](const Cdt::Point& p) { return mortonCode(p.x(), p.y(), lo, extent); };
  std::stable_sort(inside.begin(), inside.end(), [&](const auto& a, const auto& b) { return morton(a->point()) < morton(b->point()); });
  std::vector<Cdt::Vertex_handle> order(control);
  order.insert(order.end(), onEdge.begin(), onEdge.end());
  const Index nb = Index(order.size());
  order.insert(order.end(), inside.begin(), inside.end());
  // Interior vertices outside the domain cannot occur (only the cage's own points are inserted
  // outside it); the face loop below checks indices anyway.
  const Index nv = Index(order.size());
  out.boundary = nb;
  out.V.resize(nv, 2);
  out.edge.setConstant(nv, 2, -1);
  out.t.setZero(nv);
  for (Index i = 0; i < nv; ++i) {
    auto& info = order[std::size_t(i)]->info();
    info.control = int(i);  // reused as the vertex index from here on
    const auto& p = order[std::size_t(i)]->point();
    out.V.row(i) = Vec2(p.x(), p.y());
    if (i >= m && i < nb) {
      const auto [k, l] = edges[std::size_t(info.edge)];
      out.edge.row(i) << k, l;
      out.t(i) = info.t;
      out.V.row(i) = (1.0 - info.t) * C.row(k) + info.t * C.row(l);
    }
  }
  std::vector<std::pair<std::uint32_t, std::array<int, 3>>> faces;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->is_in_domain()) {
      const auto c = CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
      faces.push_back({morton(c), {f->vertex(0)->info().control, f->vertex(1)->info().control, f->vertex(2)->info().control}});
    }
  std::stable_sort(faces.begin(), faces.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  out.T.reserve(faces.size());
  for (const auto& f : faces) out.T.push_back(f.second);
  return out;
}

ConstrainedTriangulation constrainedTriangulation(const Points& points, const std::vector<std::array<int, 2>>& segments) {
  const Index np = points.rows();
  if (!points.allFinite()) throw std::invalid_argument("constrained triangulation: a point is not finite");
  for (const auto& [a, b] : segments)
    if (a < 0 || b < 0 || a >= np || b >= np)
      throw std::invalid_argument("constrained triangulation: segment (" + std::to_string(a) + ", " + std::to_string(b) +
                                  ") is out of range for " + std::to_string(np) + " points");
  std::vector<std::pair<PlainCdt::Point, int>> input;
  input.reserve(std::size_t(np));
  for (Index i = 0; i < np; ++i) input.emplace_back(PlainCdt::Point(points(i, 0), points(i, 1)), int(i));
  PlainCdt cdt;
  cdt.insert(input.begin(), input.end());  // spatially sorted
  std::vector<PlainCdt::Vertex_handle> handle(static_cast<std::size_t>(np));
  std::vector<std::uint8_t> have(static_cast<std::size_t>(np), 0);
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    handle[std::size_t(v->info())] = v;
    have[std::size_t(v->info())] = 1;
  }
  for (Index i = 0; i < np; ++i)  // merged duplicates: the vertex that holds the point
    if (!have[std::size_t(i)]) handle[std::size_t(i)] = cdt.insert(input[std::size_t(i)].first);
  ConstrainedTriangulation out;
  std::vector<Vec2> added;
  for (const auto& [a, b] : segments)
    if (handle[std::size_t(a)] != handle[std::size_t(b)]) cdt.insert_constraint(handle[std::size_t(a)], handle[std::size_t(b)]);
  // Crossings of segments were inserted by CGAL without a row: number them after the points.
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    const bool known = v->info() >= 0 && v->info() < np && have[std::size_t(v->info())] && handle[std::size_t(v->info())] == PlainCdt::Vertex_handle(v);
    if (known) continue;
    v->info() = int(np + Index(added.size()));
    added.emplace_back(v->point().x(), v->point().y());
  }
  out.V.resize(np + Index(added.size()), 2);
  out.V.topRows(np) = points;
  for (std::size_t k = 0; k < added.size(); ++k) out.V.row(np + Index(k)) = added[k];
  out.T.reserve(cdt.number_of_faces());
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    out.T.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  return out;
}

double estimateMeshVertices(const Cage& cage, double spacing) {
  double perimeter = 0.0;
  for (const auto& [k, l] : cageEdges(cage)) perimeter += (cage.C.row(k) - cage.C.row(l)).norm();
  return kVerticesPerSquareSpacing * std::abs(signedArea(cage.C)) / (spacing * spacing) + perimeter / spacing;
}

double spacingForVertexCount(const Cage& cage, Index targetVertices, double minAngleDegrees) {
  if (targetVertices < 3 * cage.size()) throw std::invalid_argument("LBC mesh: the vertex count must be at least 3m");
  // A Delaunay-refined mesh with edges ≤ h has about 2.45 vertices per h² of area; one trial mesh
  // at a 4× coarser count corrects the constant for this cage (vertices ∝ 1/h²).
  const double area = std::abs(signedArea(cage.C));
  CageMeshOptions options;
  options.minAngleDegrees = minAngleDegrees;
  const Index trial = std::max<Index>(targetVertices / 4, 3 * cage.size());
  options.spacing = std::sqrt(kVerticesPerSquareSpacing * area / double(trial));
  const Index got = meshCageInterior(cage, options).size();
  return options.spacing * std::sqrt(double(got) / double(targetVertices));
}

}  // namespace kc
