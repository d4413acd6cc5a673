// A test backend: mean value coordinates (Floater 2003; Hormann and Floater 2006 for any simple
// polygon) inside a closed polygonal cage. It proves that a backend is one class and one
// registration line: nothing else in kcwarp names it, yet `kcwarp-cli bind --backend mvc` binds
// with it, sessions save and load it and its report, `stats` shows that report, its parameter
// shows in the Bind panel, and the conformance suite runs on it. Linked into the test executables that use it (tests/CMakeLists.txt).

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kc/app/backend.h"
#include "kc/core/cage.h"
#include "kc/core/field/field.h"

namespace kc::test {
namespace {

/// Mean value coordinates of a simple polygon, evaluated in closed form: nodes = the m controls,
/// Coef = I, E(P) = the coordinates at P. Defined inside the polygon (and on it: linear along each
/// edge, Lagrange at the vertices); a point outside has an empty row.
class MvcField final : public CoordinateField {
 public:
  MvcField(Points C, double vertexTolerance) : m_C(std::move(C)), m_tolerance(vertexTolerance) {}

  Index controls() const override { return m_C.rows(); }
  Index nodes() const override { return m_C.rows(); }
  bool ready() const override { return true; }
  FieldDomain domain() const override { return FieldDomain::Mesh; }
  std::string_view kind() const override { return "mvc"; }

  bool contains(const Vec2& p) const override {  // even-odd rule, points on an edge inside
    bool inside = false;
    const Index m = m_C.rows();
    for (Index i = 0, j = m - 1; i < m; j = i++) {
      const Vec2 a = m_C.row(i).transpose(), b = m_C.row(j).transpose();
      if (onSegment(p, a, b)) return true;
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
        inside = !inside;
    }
    return inside;
  }

  SparseRowMatrix evaluationOperator(const Points& P) const override {
    if (!P.allFinite()) throw std::invalid_argument("mvc field: points must be finite");
    std::vector<Eigen::Triplet<double, Index>> entries;
    std::vector<double> w;
    for (Index r = 0; r < P.rows(); ++r) {
      const Vec2 p = P.row(r).transpose();
      if (!contains(p)) continue;
      coordinates(p, w);
      for (Index i = 0; i < m_C.rows(); ++i)
        if (w[static_cast<std::size_t>(i)] != 0.0) entries.emplace_back(r, i, w[static_cast<std::size_t>(i)]);
    }
    SparseRowMatrix E(P.rows(), m_C.rows());
    E.setFromTriplets(entries.begin(), entries.end());
    return E;
  }

  /// Central differences of E (step 1e-6 of the cage's size): a test backend's gradients.
  void gradientOperators(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const override {
    const double h = 1e-6 * (m_C.colwise().maxCoeff() - m_C.colwise().minCoeff()).norm();
    Points shifted = P;
    auto difference = [&](int axis) {
      shifted.col(axis).array() += h;
      const SparseRowMatrix plus = evaluationOperator(shifted);
      shifted.col(axis).array() -= 2.0 * h;
      const SparseRowMatrix minus = evaluationOperator(shifted);
      shifted.col(axis) = P.col(axis);
      return SparseRowMatrix((plus - minus) / (2.0 * h));
    };
    Ex = difference(0);
    Ey = difference(1);
  }

  RowMatrix coefficientColumns(std::span<const Index> columns) const override {
    const std::vector<Index> cols = detail::fieldColumns(columns, m_C.rows());
    RowMatrix coef = RowMatrix::Zero(m_C.rows(), static_cast<Index>(cols.size()));
    for (std::size_t k = 0; k < cols.size(); ++k) coef(cols[k], static_cast<Index>(k)) = 1.0;
    return coef;
  }

  void update(const Weights&, std::span<const Index>) override {
    throw std::logic_error("mvc field: its weights follow from the cage alone and cannot be changed");
  }

 private:
  bool onSegment(const Vec2& p, const Vec2& a, const Vec2& b) const {
    const Vec2 ab = b - a, ap = p - a;
    const double len = ab.norm();
    return std::abs(ab.x() * ap.y() - ab.y() * ap.x()) <= m_tolerance * len && ap.dot(ab) >= 0.0 && ap.dot(ab) <= len * len;
  }

  /// w (length m) at p inside or on the polygon.
  void coordinates(const Vec2& p, std::vector<double>& w) const {
    const Index m = m_C.rows();
    w.assign(static_cast<std::size_t>(m), 0.0);
    std::vector<Vec2> s(static_cast<std::size_t>(m));
    std::vector<double> r(static_cast<std::size_t>(m));
    for (Index i = 0; i < m; ++i) {
      s[static_cast<std::size_t>(i)] = m_C.row(i).transpose() - p;
      r[static_cast<std::size_t>(i)] = s[static_cast<std::size_t>(i)].norm();
      if (r[static_cast<std::size_t>(i)] <= m_tolerance) {  // at a vertex: Lagrange
        w[static_cast<std::size_t>(i)] = 1.0;
        return;
      }
    }
    for (Index i = 0; i < m; ++i) {  // on an edge: linear between its ends (4.7)
      const Index j = (i + 1) % m;
      if (onSegment(p, m_C.row(i).transpose(), m_C.row(j).transpose())) {
        const double t = (p - m_C.row(i).transpose()).norm() / (m_C.row(j) - m_C.row(i)).norm();
        w[static_cast<std::size_t>(i)] = 1.0 - t;
        w[static_cast<std::size_t>(j)] = t;
        return;
      }
    }
    // tan(α_i/2) = 2A_i / (r_i r_{i+1} + D_i), α_i the signed angle at p from v_i to v_{i+1}.
    std::vector<double> tanHalf(static_cast<std::size_t>(m));
    for (Index i = 0; i < m; ++i) {
      const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>((i + 1) % m);
      const double cross = s[a].x() * s[b].y() - s[a].y() * s[b].x(), dot = s[a].dot(s[b]);
      tanHalf[a] = cross / (r[a] * r[b] + dot);
    }
    double sum = 0.0;
    for (Index i = 0; i < m; ++i) {
      const auto k = static_cast<std::size_t>(i), prev = static_cast<std::size_t>((i + m - 1) % m);
      w[k] = (tanHalf[prev] + tanHalf[k]) / r[k];
      sum += w[k];
    }
    for (double& x : w) x /= sum;
  }

  Points m_C;
  double m_tolerance;
};

/// The mvc backend's own report: the controls it bound and the snap distance it used.
class MvcReport final : public app::BackendReport {
 public:
  MvcReport(Index controls, double snap) : m_controls(controls), m_snap(snap) {}
  std::string summary() const override {
    return "mean value coordinates of " + std::to_string(m_controls) + " control points, snap " + shortText(m_snap) + " px";
  }
  std::string brief() const override { return std::to_string(m_controls) + " control points"; }
  std::string details(const app::BindParams&, const char* indent) const override {
    return std::string(indent) + "MVC: closed-form weights, nothing iterated\n";
  }
  void toJson(nlohmann::json& out, bool) const override { out = {{"controls", m_controls}, {"snap", m_snap}}; }
  static std::shared_ptr<const app::BackendReport> fromJson(const nlohmann::json& j) {
    if (!j.is_object() || !j.contains("controls") || !j.contains("snap")) return nullptr;
    return std::make_shared<MvcReport>(j["controls"].get<Index>(), j["snap"].get<double>());
  }

 private:
  static std::string shortText(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
  }
  Index m_controls;
  double m_snap;
};

/// The "mvc" backend: one closed polygon, no samples beyond its controls, no targets.
class MvcBackend final : public app::Backend {
 public:
  std::string_view name() const override { return "mvc"; }
  std::string_view displayName() const override { return "MVC"; }
  std::string_view description() const override { return "mean value coordinates inside the cage (a test backend)"; }
  std::string_view parameterBlock() const override { return "mvc"; }

  /// One parameter, stored in BindParams::values: the distance (pixels) within which a point counts
  /// as on the cage (Lagrange at a vertex, linear along an edge).
  const std::vector<app::BackendParameter>& parameters() const override {
    static const std::vector<app::BackendParameter> described = [] {
      app::BackendParameter snap;
      snap.key = "snap";
      snap.label = "MVC snap";
      snap.help = "Distance in pixels within which a point counts as on the cage";
      snap.tooltip = "Points this close to the cage take the cage's own weights.";
      snap.min = 1e-12;
      snap.max = 1.0;
      snap.logarithmic = true;
      snap.defaultValue = 1e-9;
      return std::vector<app::BackendParameter>{snap};
    }();
    return described;
  }

  app::BackendCapabilities capabilities() const override {
    app::BackendCapabilities c;
    c.why = "mean value coordinates follow from the cage alone";
    return c;
  }

  void bind(app::Session& s, const app::BindStep& step) const override {
    step("coordinates", 0.0);
    const Index m = s.cage.size();
    if (!isClosedPolygon(s.cage)) throw std::invalid_argument("the mvc backend binds one closed polygon");
    s.samples = {};
    s.samples.X = s.cage.C;
    s.samples.kind.assign(static_cast<std::size_t>(m), SampleKind::Control);
    s.samples.edge.setConstant(m, 2, -1);
    s.sigma = 0.0;
    s.W = Weights::Identity(m, m);
    s.W0.resize(0, 0);
    rebuildField(s);
    s.report.sampling = {};
    s.report.sampling.controls = m;
    s.report.optimize = {};
    s.report.optimize.solved = m;
    s.report.backend = std::make_shared<MvcReport>(m, app::parameterValue(*this, parameters().front(), s.params));
  }

  std::shared_ptr<const app::BackendReport> readReport(const nlohmann::json& block) const override {
    return MvcReport::fromJson(block);
  }

  void rebuildField(app::Session& s) const override {
    const double snap = app::parameterValue(*this, parameters().front(), s.params);
    s.field = std::make_unique<MvcField>(s.cage.C, snap);
  }

  OptimizeReport reoptimize(app::Session&, Method, std::span<const Index>, std::vector<Index>*) const override {
    throw std::invalid_argument("the mvc backend has no per-sample optimization");
  }
};

const MvcBackend& mvcBackend() {
  static const MvcBackend backend;
  return backend;
}

}  // namespace

const bool kMvcRegistered = app::registerBackend(mvcBackend());

}  // namespace kc::test
