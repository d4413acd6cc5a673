// Rigid regions in the kernel backend (thesis 5.4, docs/rigidity.md).

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <numeric>
#include <stdexcept>

#include "backends.h"
#include "kc/core/structure/line_blend.h"
#include "kc/app/pipeline.h"
#include "kc/app/rigidity.h"
#include "kc/core/kernel/interpolator.h"

namespace kc::app {

/// The samples rigidity keeps: controls (Lagrange) and line samples. Cage-edge samples are not held:
/// held, they left the nodes near the cage too few degrees of freedom (docs/rigidity.md, "Held samples").
std::vector<char> rigidHeldSamples(const SampleSet& samples) {
  std::vector<char> keep(static_cast<std::size_t>(samples.size()), 0);
  for (Index i = 0; i < samples.size(); ++i) {
    const SampleKind k = samples.kind[static_cast<std::size_t>(i)];
    keep[static_cast<std::size_t>(i)] = k == SampleKind::Control || k == SampleKind::Line;
  }
  return keep;
}

RigidityReport applyRigidity(Session& s, KernelField& field, const Progress& progress) {
  if (!s.hasRigidity()) return {};
  if (Index(s.rigidity.size()) != s.samples.size())
    throw std::invalid_argument("the session's rigidity has " + std::to_string(s.rigidity.size()) + " entries for " +
                                std::to_string(s.samples.size()) + " samples");
  RigidityOptions options;
  options.solver.progress = progress;
  // The lobe lift's bumps would bend the rigid regions: none with rigidity (liftFieldLobes).
  const bool lifted = field.lift().size() > 0;
  field.clearLift();
  RigidityReport r = makeRigid(field, s.cage.C, s.rigidity, rigidHeldSamples(s.samples), s.W, options);
  if (lifted) {
    r.columns.resize(static_cast<std::size_t>(s.W.cols()));
    std::iota(r.columns.begin(), r.columns.end(), Index(0));
  }
  return r;
}

void restoreUnconstrained(Session& s, KernelField& field, std::span<const Index> rowsIn, std::vector<Index>& columns) {
  const Index m = s.W.cols();
  std::vector<Index> rows(rowsIn.begin(), rowsIn.end());
  const bool lines = !s.structure.lines.empty() || s.params.kc.linearEdges;
  if (!s.structure.lines.empty() && !s.params.kc.exactLines) {  // the lines' neighbourhoods start again from the optimizer's weights, as at the bind
    const std::vector<Index> near = lineNeighbourhoodRows(s.cage, s.structure.lines, s.samples.X, s.sigma);
    rows.insert(rows.end(), near.begin(), near.end());
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }
  const ExteriorContinuation continuation = continuationFor(s);
  rows = rederivedRows(s, continuation, rows);  // and the continued exterior rows that read them
  const RowMatrix before = s.W;
  optimizeRows(s, s.params.kc.method, rows, continuation);
  if (lines) {
    field.update(s.W);  // applyLines blends from the field of the weights before the lines
    applyLines(s, field);
    for (Index c = 0; c < m; ++c) columns.push_back(c);
    return;
  }
  for (Index c = 0; c < m; ++c)
    for (Index i : rows)
      if (s.W(i, c) != before(i, c)) {
        columns.push_back(c);
        break;
      }
  if (!columns.empty()) field.update(s.W, columns);
}

RigidityUpdate setRigidity(Session& s, std::span<const double> rho, const StageProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  auto* field = dynamic_cast<KernelField*>(s.field.get());
  if (!field || !s.hasField()) throw std::invalid_argument("rigid regions need a session bound with the kernel backend (kc)");
  if (s.W0.rows() != s.samples.size() || s.W0.cols() != s.cage.size())
    throw std::invalid_argument("this session has no target weights (weights.initial) to restore the unconstrained weights from");
  if (Index(rho.size()) != s.samples.size())
    throw std::invalid_argument("rigidity needs one value per sample (" + std::to_string(s.samples.size()) + "), got " +
                                std::to_string(rho.size()));
  for (double r : rho)
    if (!(r >= 0.0 && r <= 1.0)) throw std::invalid_argument("rigidity values must lie in [0, 1]");

  RigidityUpdate u;
  std::vector<Index> rows = s.rigidity.size() == rho.size() ? rigidityZone(*field, s.rigidity) : std::vector<Index>{};
  const std::vector<Index> fresh = rigidityZone(*field, rho);
  rows.insert(rows.end(), fresh.begin(), fresh.end());
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  double shown = 0.0;  // the bar never goes back (the solver's own estimate may)
  auto tell = [&](const char* stage, double f) { return !progress || progress(stage, shown = std::max(shown, f)); };
  auto step = [&](const char* stage, double f) {
    if (!tell(stage, f)) throw Cancelled();
  };
  const RowMatrix W = s.W, lift = field->lift();
  const std::vector<double> stored = s.rigidity;
  s.rigidity.assign(rho.begin(), rho.end());
  if (!rows.empty()) try {
    step("restoring the unconstrained weights", 0.0);
    restoreUnconstrained(s, *field, rows, u.columns);
    step("rigidity solve", 0.1);
    u.report = applyRigidity(s, *field, [&](double f) { return tell("rigidity solve", 0.1 + 0.85 * f); });
    step("field", 0.95);
    u.columns.insert(u.columns.end(), u.report.columns.begin(), u.report.columns.end());
    std::sort(u.columns.begin(), u.columns.end());
    u.columns.erase(std::unique(u.columns.begin(), u.columns.end()), u.columns.end());
  } catch (const Cancelled&) {  // put the session back as it was
    s.W = W;
    s.rigidity = stored;
    field->update(s.W);
    field->setLift(lift);
    throw;
  }
  u.rows = std::move(rows);
  u.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return u;
}

RigidityFigures measureRigidity(const Session& s, const Points& polygon, const Pose& pose, double step) {
  if (!s.hasField()) throw std::invalid_argument("measureRigidity: the session has no field");
  if (polygon.rows() < 3 || !(step > 0.0)) throw std::invalid_argument("measureRigidity: a polygon of >= 3 points and a step > 0");
  const Eigen::RowVector2d lo = polygon.colwise().minCoeff(), hi = polygon.colwise().maxCoeff();
  std::vector<Vec2> inside;
  for (double y = lo.y() + 0.5 * step; y < hi.y(); y += step)
    for (double x = lo.x() + 0.5 * step; x < hi.x(); x += step)
      if (insidePolygon(polygon, Vec2(x, y))) inside.emplace_back(x, y);
  if (inside.empty()) throw std::invalid_argument("measureRigidity: no grid point inside the polygon");
  Points P(Index(inside.size()), 2);
  for (std::size_t k = 0; k < inside.size(); ++k) P.row(Index(k)) = inside[k].transpose();
  const Weights W = s.field->weightsAt(P);
  Weights dx, dy;
  s.field->gradientsAt(P, dx, dy);
  const std::vector<Affine2> T = handleTransforms(s.cage.C, pose.empty() ? restPose(s.cage.size()) : pose);
  RigidityFigures f;
  f.points = P.rows();
  f.unity = (W.rowwise().sum().array() - 1.0).abs().maxCoeff();
  f.reproduction = (W * s.cage.C - P).cwiseAbs().maxCoeff();
  f.minWeight = W.minCoeff();
  for (Index p = 0; p < P.rows(); ++p) {
    const Eigen::Matrix2d J = deformationJacobian(P.row(p).transpose(), W.row(p).transpose(), dx.row(p).transpose(), dy.row(p).transpose(), T);
    Eigen::JacobiSVD<Eigen::Matrix2d> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix2d D = Eigen::Matrix2d::Identity();
    D(1, 1) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
    const Eigen::Matrix2d R = svd.matrixU() * D * svd.matrixV().transpose();
    f.distortion += (J - R).norm();
  }
  f.distortion /= double(P.rows());
  return f;
}

StarLegSetup starLegSetup(const Cage& star) {
  if (star.size() != 10) throw std::invalid_argument("starLegSetup: expects a 10-point star");
  StarLegSetup st;
  const Points& C = star.C;
  st.centroid = polygonCentroid(C);
  const Vec2 p3 = C.row(3).transpose(), p4 = C.row(4).transpose(), p5 = C.row(5).transpose(), mid = 0.5 * (p3 + p5);
  st.polygon.resize(3, 2);
  st.polygon.row(0) = (p3 + 0.12 * (p5 - p3)).transpose();
  st.polygon.row(1) = (p5 + 0.12 * (p3 - p5)).transpose();
  st.polygon.row(2) = (mid + 0.55 * (p4 - mid)).transpose();
  st.pose = restPose(star.size());
  st.pose[4].translate = 40.0 * (st.centroid - p4).normalized();
  return st;
}

}  // namespace kc::app
