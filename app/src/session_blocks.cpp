#include "session_blocks.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "base64.h"
#include "kc/app/errors.h"
#include "kc/app/limits.h"
#include "kc/app/text.h"
#include "kc/core/field/kernel_field.h"
#include "kc/core/field/mesh_field.h"

namespace kc::app::detail {

json weightsToJson(const Weights& W) {
  json rows = json::array();
  for (Index i = 0; i < W.rows(); ++i) {
    json r = json::array();
    for (Index k = 0; k < W.cols(); ++k) r.push_back(W(i, k));
    rows.push_back(std::move(r));
  }
  return rows;
}

Weights parseWeights(const json& rows, Index n, Index m, const std::string& where, const std::string& field) {
  if (!rows.is_array()) throw InputError(where, field + " must be an array of rows");
  if (static_cast<Index>(rows.size()) != n)
    throw InputError(where, field + " has " + std::to_string(rows.size()) + " rows but there are " + std::to_string(n) + " samples");
  Weights W(n, m);
  for (Index i = 0; i < n; ++i) {
    const json& r = rows[static_cast<std::size_t>(i)];
    if (!r.is_array() || static_cast<Index>(r.size()) != m)
      throw InputError(where, field + "[" + std::to_string(i) + "] must have " + std::to_string(m) + " weights (one per control point)");
    for (Index k = 0; k < m; ++k) {
      const json& v = r[static_cast<std::size_t>(k)];
      W(i, k) = boundedNumber(v, kMaxWeight, where, field + "[" + std::to_string(i) + "][" + std::to_string(k) + "]");
    }
  }
  return W;
}

namespace {

/// Largest relative difference between the area a mesh field's triangles cover and the cage's.
constexpr double kMeshAreaTolerance = 1e-9;

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);
constexpr bool kLittleEndian = std::endian::native == std::endian::little;

/// The 8 bytes of `v` in little-endian order, in place (nothing to do on little-endian machines).
void toLittleEndian(unsigned char* bytes) {
  if constexpr (!kLittleEndian)
    for (int i = 0; i < 4; ++i) std::swap(bytes[i], bytes[7 - i]);
}

/// Stored kernel-field coefficients ([B; U], field.coefficients_b64) may be larger than weights:
/// U = K⁻¹(W − PB) grows with K's condition number.
constexpr double kMaxCoefficient = 1e12;

Weights parseCompactWeights(const json& block, Index n, Index m, const std::string& where, const std::string& field,
                            double limit = kMaxWeight) {
  if (!block.is_object()) throw InputError(where, field + " must be an object {\"shape\", \"dtype\", \"base64\"}");
  const json& shape = require(block, "shape", where);
  if (!shape.is_array() || shape.size() != 2) throw InputError(where, field + ".shape must be [rows, columns]");
  const long long rows = integerInRange(shape[0], 0, std::numeric_limits<int>::max(), where, field + ".shape[0]");
  const long long cols = integerInRange(shape[1], 0, std::numeric_limits<int>::max(), where, field + ".shape[1]");
  if (rows != n || cols != m)
    throw InputError(where, field + ".shape is [" + std::to_string(rows) + ", " + std::to_string(cols) + "] but the session has " +
                                std::to_string(n) + " rows (samples) and " + std::to_string(m) + " control points");
  if (block.contains("dtype") && block["dtype"] != "f64le")
    throw InputError(where, field + ".dtype " + quoted(block["dtype"]) + " is not \"f64le\"");
  const json& text = require(block, "base64", where);
  if (!text.is_string()) throw InputError(where, field + ".base64 must be a string");
  const std::string& b64 = text.get_ref<const std::string&>();
  const std::size_t bytes = static_cast<std::size_t>(n) * static_cast<std::size_t>(m) * sizeof(double);
  const std::size_t expected = (bytes + 2) / 3 * 4;
  if (b64.size() != expected)
    throw InputError(where, field + ".base64 has " + std::to_string(b64.size()) + " characters, but " + std::to_string(n) + "x" +
                                std::to_string(m) + " doubles need " + std::to_string(expected) +
                                (b64.size() < expected ? " (truncated)" : ""));
  std::string raw, problem;
  raw.reserve(bytes);
  if (!base64Decode(b64, raw, problem) || raw.size() != bytes)
    throw InputError(where, field + ".base64 is not valid base64: " + (problem.empty() ? "wrong padding" : problem));
  Weights W(n, m);
  for (Index i = 0; i < n; ++i)
    for (Index k = 0; k < m; ++k) {
      unsigned char b[8];
      std::memcpy(b, raw.data() + (static_cast<std::size_t>(i) * static_cast<std::size_t>(m) + static_cast<std::size_t>(k)) * 8, 8);
      toLittleEndian(b);
      double v;
      std::memcpy(&v, b, 8);
      if (!std::isfinite(v) || std::abs(v) > limit)
        throw InputError(where, field + "[" + std::to_string(i) + "][" + std::to_string(k) + "] is " + format("%.17g", v) +
                                    (!std::isfinite(v)       ? ", not a finite number"
                                     : limit == kMaxWeight ? ", beyond kcwarp's limit |w| <= 1e6"
                                                             : ", beyond kcwarp's limit of " + json(limit).dump()));
      W(i, k) = v;
    }
  return W;
}

/// A mesh field's mesh must cover the cage: vertices within the cage's bounds, no triangle twice,
/// every triangle oriented alike (none inverted), and the triangles' areas summing to the area the
/// cage encloses within kMeshAreaTolerance (relative). InputError naming the check otherwise.
void checkMeshCoversCage(const Points& V, const Triangles& T, const Cage& cage, const std::string& where) {
  const Eigen::RowVector2d lo = cage.C.colwise().minCoeff(), hi = cage.C.colwise().maxCoeff();
  const double slack = 1e-9 * (1.0 + (hi - lo).maxCoeff() + cage.C.cwiseAbs().maxCoeff());
  for (Index i = 0; i < V.rows(); ++i)
    if (!((V.row(i).array() >= lo.array() - slack).all() && (V.row(i).array() <= hi.array() + slack).all()))
      throw InputError(where, "field.vertices[" + std::to_string(i) + "] = (" + format("%.6g", V(i, 0)) + ", " + format("%.6g", V(i, 1)) +
                                  ") lies outside the cage's bounds [" + format("%.6g", lo.x()) + ", " + format("%.6g", hi.x()) + "] x [" +
                                  format("%.6g", lo.y()) + ", " + format("%.6g", hi.y()) + "]");
  std::map<std::array<int, 3>, std::size_t> seen;
  double covered = 0.0, sign = 0.0;
  for (std::size_t t = 0; t < T.size(); ++t) {
    std::array<int, 3> key = T[t];
    std::sort(key.begin(), key.end());
    if (const auto [it, fresh] = seen.emplace(key, t); !fresh)
      throw InputError(where, "field.triangles[" + std::to_string(t) + "] repeats field.triangles[" + std::to_string(it->second) + "]");
    const Vec2 a = V.row(T[t][0]).transpose(), b = V.row(T[t][1]).transpose(), c = V.row(T[t][2]).transpose();
    const double area = 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    if (sign == 0.0) sign = area > 0.0 ? 1.0 : -1.0;
    if (!(area * sign > 0.0))
      throw InputError(where, "field.triangles[" + std::to_string(t) + "] is inverted or flat (oriented unlike field.triangles[0])");
    covered += std::abs(area);
  }
  if (!cage.closed) return;
  const double enclosed = std::abs(signedArea(cage.C));
  if (!(std::abs(covered - enclosed) <= kMeshAreaTolerance * enclosed))
    throw InputError(where, "field.triangles cover " + format("%.9g", covered) + " px² but the cage encloses " + format("%.9g", enclosed) +
                                " px² (a mesh field covers the cage: relative difference <= " + format("%g", kMeshAreaTolerance) + ")");
}

}  // namespace

json weightsToCompactJson(const Weights& W) {
  std::string raw(static_cast<std::size_t>(W.rows()) * static_cast<std::size_t>(W.cols()) * sizeof(double), '\0');
  std::size_t o = 0;
  for (Index i = 0; i < W.rows(); ++i)
    for (Index k = 0; k < W.cols(); ++k, o += 8) {
      const double v = W(i, k);
      unsigned char b[8];
      std::memcpy(b, &v, 8);
      toLittleEndian(b);
      std::memcpy(raw.data() + o, b, 8);
    }
  return {{"shape", {W.rows(), W.cols()}}, {"dtype", "f64le"}, {"base64", base64Encode(raw.data(), raw.size())}};
}

void putWeights(json& block, const std::string& key, const Weights& W, WeightsForm form) {
  if (form == WeightsForm::Compact)
    block[key + "_b64"] = weightsToCompactJson(W);
  else
    block[key] = weightsToJson(W);
}

Weights getWeights(const json& block, const std::string& key, Index n, Index m, const std::string& where,
                   const std::string& field) {
  const std::string compact = key + "_b64";
  const bool hasRows = block.contains(key), hasCompact = block.contains(compact);
  if (hasRows && hasCompact) throw InputError(where, field + " and " + field + "_b64 are both given (keep one)");
  if (hasCompact) return parseCompactWeights(block[compact], n, m, where, field + "_b64");
  if (!hasRows) throw InputError(where, "missing key '" + key + "' (or '" + compact + "')");
  return parseWeights(block[key], n, m, where, field);
}

namespace {

/// A built-in field kind belongs to the backends with targets (a kernel field) or without (a mesh):
/// InputError when s.params.backend is of the other sort.
void requireBackendOf(const char* kind, bool targets, const Session& s, const std::string& where) {
  if (backendFor(s.params.backend).capabilities().targets == targets) return;
  throw InputError(where, std::string("field.kind \"") + kind + "\" does not match params.backend \"" + s.params.backend +
                              "\" (its field is " + (targets ? "a mesh" : "a kernel field") + ")");
}

json meshFieldToJson(const Session& s, WeightsForm form) {
  const auto* mesh = static_cast<const MeshField*>(s.field.get());
  json tris = json::array();
  for (const auto& t : mesh->triangles()) tris.push_back({t[0], t[1], t[2]});
  json block = {{"kind", "mesh"}, {"vertices", pointsToJson(mesh->vertices())}, {"triangles", tris}};
  putWeights(block, "weights", mesh->vertexWeights(), form);
  return block;
}

json kernelFieldToJson(const Session& s, WeightsForm form) {
  const auto* kernel = static_cast<const KernelField*>(s.field.get());
  const KernelInterpolator& k = kernel->interpolator();
  json block = {{"kind", "kernel"},
                {"nodes", "samples"},
                {"sigma", k.kernel().sigma},
                {"spacing", s.params.spacing},
                {"interp", std::string(toString(k.mode()))}};
  // The solved coefficients [B; U], so that a load needs no factorization (the compact form only).
  if (form == WeightsForm::Compact && kernel->ready())
    block["coefficients_b64"] = weightsToCompactJson(kernel->coefficientColumns());
  // The lobe lift (KernelField::lift), its non-zero rows: the stored coefficients hold it.
  if (form == WeightsForm::Compact && kernel->lift().size() > 0) {
    const RowMatrix& L = kernel->lift();
    std::vector<Index> rows;
    for (Index i = 0; i < L.rows(); ++i)
      if (L.row(i).cwiseAbs().maxCoeff() > 0.0) rows.push_back(i);
    RowMatrix values(static_cast<Index>(rows.size()), L.cols());
    for (std::size_t k = 0; k < rows.size(); ++k) values.row(static_cast<Index>(k)) = L.row(rows[k]);
    block["lift_rows"] = rows;
    block["lift_b64"] = weightsToCompactJson(values);
  }
  return block;
}

bool meshFieldFromJson(const json& block, Session& s, const std::string& where) {
  requireBackendOf("mesh", false, s, where);
  const Points V = parsePoints(require(block, "vertices", where), where, "field.vertices");
  const Index m = s.cage.size();
  if (V.rows() < m) throw InputError(where, "field.vertices must start with the " + std::to_string(m) + " control points");
  for (Index i = 0; i < m; ++i)
    if ((V.row(i) - s.cage.C.row(i)).norm() > 1e-9 * (1.0 + s.cage.C.row(i).norm()))
      throw InputError(where, "field.vertices[" + std::to_string(i) + "] differs from cage point " + std::to_string(i));
  const json& tris = require(block, "triangles", where);
  if (!tris.is_array() || tris.empty()) throw InputError(where, "field.triangles must be a non-empty array of [i, j, k]");
  Triangles T;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const json& r = tris[t];
    const std::string name = "field.triangles[" + std::to_string(t) + "]";
    if (!r.is_array() || r.size() != 3) throw InputError(where, name + " must be [i, j, k]");
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      tri[static_cast<std::size_t>(k)] = static_cast<int>(
          integerInRange(r[static_cast<std::size_t>(k)], 0, V.rows() - 1, where, name + "[" + std::to_string(k) + "]"));
    }
    T.push_back(tri);
  }
  checkMeshCoversCage(V, T, s.cage, where);
  Weights W = getWeights(block, "weights", V.rows(), m, where, "field.weights");
  checkWeightRows(W, V, s.cage.C, where, "field.weights");
  try {
    s.field = std::make_unique<MeshField>(V, std::move(T), std::move(W));
  } catch (const std::invalid_argument& e) {
    throw InputError(where, std::string("field: ") + e.what());
  }
  return true;
}

/// The lobe lift of a kernel block (lift_rows, lift_b64): #S×m, empty without one.
RowMatrix liftFromJson(const json& block, const Session& s, const std::string& where) {
  if (!block.contains("lift_rows") && !block.contains("lift_b64")) return {};
  const json& rows = require(block, "lift_rows", where);
  if (!rows.is_array()) throw InputError(where, "field.lift_rows must be an array of sample indices");
  const Index n = s.samples.size(), m = s.cage.size();
  const RowMatrix values = parseCompactWeights(require(block, "lift_b64", where), static_cast<Index>(rows.size()), m, where,
                                               "field.lift_b64", kMaxCoefficient);
  RowMatrix L = RowMatrix::Zero(n, m);
  for (std::size_t k = 0; k < rows.size(); ++k)
    L.row(integerInRange(rows[k], 0, n - 1, where, "field.lift_rows[" + std::to_string(k) + "]")) =
        values.row(static_cast<Index>(k));
  return L;
}

bool kernelFieldFromJson(const json& block, Session& s, const std::string& where) {
  requireBackendOf("kernel", true, s, where);
  if (block.contains("sigma") && std::abs(finiteNumber(block["sigma"], where, "field.sigma") - s.sigma) > 1e-12 * s.sigma)
    throw InputError(where, "field.sigma disagrees with params.sigma");
  if (block.contains("interp") && block["interp"] != std::string(toString(s.params.kc.interp)))
    throw InputError(where, "field.interp disagrees with params.interp");
  if (block.contains("coefficients_b64") && s.sigma > 0) {  // checked against the weights by the backend's rebuildField
    const Index n = KernelField::kPolynomialNodes + s.samples.size();
    const RowMatrix coef =
        parseCompactWeights(block["coefficients_b64"], n, s.cage.size(), where, "field.coefficients_b64", kMaxCoefficient);
    auto field = std::make_unique<KernelField>();
    try {
      GaussianKernel kernel = GaussianKernel::forSpacing(s.sigma, s.params.spacing);
      kernel.width = s.sizing;
      field->restore(s.samples.X, kernel, s.params.kc.interp, coef, liftFromJson(block, s, where));
    } catch (const std::invalid_argument& e) {
      throw InputError(where, std::string("field: ") + e.what());
    }
    s.field = std::move(field);
  }
  return false;
}

}  // namespace

std::vector<FieldCodec>& fieldCodecs() {
  static std::vector<FieldCodec> codecs{{"mesh", meshFieldToJson, meshFieldFromJson},
                                        {"kernel", kernelFieldToJson, kernelFieldFromJson}};
  return codecs;
}

const FieldCodec* codecFor(std::string_view kind) {
  for (const FieldCodec& c : fieldCodecs())
    if (c.kind == kind) return &c;
  return nullptr;
}

json fieldToJson(const Session& s, WeightsForm form) {
  if (!s.field) return nullptr;
  const FieldCodec* codec = codecFor(s.field->kind());
  return codec ? codec->write(s, form) : json(nullptr);
}

bool fieldFromJson(const json& block, Session& s, const std::string& where) {
  if (!block.is_object()) throw InputError(where, "field must be an object");
  const json& kind = require(block, "kind", where);
  if (const FieldCodec* codec = kind.is_string() ? codecFor(kind.get<std::string>()) : nullptr)
    return codec->read(block, s, where);
  std::string kinds;
  for (const FieldCodec& c : fieldCodecs()) kinds += (kinds.empty() ? "\"" : ", \"") + std::string(c.kind) + "\"";
  throw InputError(where, "field.kind " + quoted(kind) + " is not one of " + kinds);
}

void checkWeightRows(const Weights& W, const Points& X, const Points& C, const std::string& where, const std::string& field) {
  const double scale = 1.0 + C.cwiseAbs().maxCoeff();
  for (Index i = 0; i < W.rows(); ++i) {
    const double unity = std::abs(W.row(i).sum() - 1.0);
    const double reproduction = (W.row(i) * C - X.row(i)).norm();
    if (!(unity <= kUnityTolerance))
      throw InputError(where, field + " row " + std::to_string(i) + " sums to " + format("%.17g", W.row(i).sum()) +
                                  " (partition of unity: |sum - 1| <= " + format("%g", kUnityTolerance) + ")");
    if (!(reproduction <= kReproductionTolerance * scale))
      throw InputError(where, field + " row " + std::to_string(i) + " reproduces its sample " + format("%.3g", reproduction) +
                                  " px away (linear reproduction: <= " + format("%g", kReproductionTolerance * scale) + " px)");
  }
}

json reportsToJson(const BindReport& r, const Backend& backend) {
  json problems = json::array();
  for (const std::string& p : r.problems()) problems.push_back(p);
  json j = {{"sampling",
             {{"converged", r.sampling.converged},
              {"iterations", r.sampling.iterations},
              {"last_move", r.sampling.lastMove},
              {"rejected_moves", r.sampling.rejectedMoves}}},
            {"init",
             {{"unreachable_samples", r.init.fallbackSamples},
              {"unscreened_samples", r.init.unscreenedSamples},
              {"iterations", r.init.iterations},
              {"steady_state", r.init.steadyState}}},
            {"optimize",
             {{"solved", r.optimize.solved},
              {"infeasible", r.optimize.infeasible},
              {"failed", r.optimize.failed},
              {"max_iterations", r.optimize.maxIterations}}},
            {"lift",
             {{"lobes", r.lift.lobes},
              {"rounds", r.lift.rounds},
              {"deepest_before", r.lift.deepestBefore},
              {"deepest_after", r.lift.deepestAfter}}},
            {"problems", problems}};
  if (r.backend && !backend.parameterBlock().empty()) r.backend->toJson(j[std::string(backend.parameterBlock())], true);
  return j;
}

BindReport reportsFromJson(const json& block, const Backend& backend) {
  BindReport r;
  if (!block.is_object()) return r;
  auto get = [&](const char* section, const char* key, auto fallback) {
    return block.contains(section) ? valueOr(block[section], key, fallback) : fallback;
  };
  r.sampling.converged = get("sampling", "converged", true);
  r.sampling.iterations = get("sampling", "iterations", 0);
  r.sampling.lastMove = get("sampling", "last_move", 0.0);
  r.sampling.rejectedMoves = get("sampling", "rejected_moves", Index{0});
  r.init.fallbackSamples = get("init", "unreachable_samples", Index{0});
  r.init.unscreenedSamples = get("init", "unscreened_samples", Index{0});
  r.init.iterations = get("init", "iterations", 0);
  r.init.steadyState = get("init", "steady_state", false);
  r.optimize.solved = get("optimize", "solved", Index{0});
  r.optimize.infeasible = get("optimize", "infeasible", Index{0});
  r.optimize.failed = get("optimize", "failed", Index{0});
  r.optimize.maxIterations = get("optimize", "max_iterations", 0);
  r.lift.lobes = get("lift", "lobes", Index{0});
  r.lift.rounds = get("lift", "rounds", 0);
  r.lift.deepestBefore = get("lift", "deepest_before", 0.0);
  r.lift.deepestAfter = get("lift", "deepest_after", 0.0);
  if (const std::string name(backend.parameterBlock()); !name.empty() && block.contains(name))
    r.backend = backend.readReport(block[name]);
  return r;
}

}  // namespace kc::app::detail

namespace kc::app {

bool registerFieldCodec(const FieldCodec& codec) {
  if (detail::codecFor(codec.kind))
    throw std::invalid_argument("field kind '" + std::string(codec.kind) + "' has a codec already");
  detail::fieldCodecs().push_back(codec);
  return true;
}

}  // namespace kc::app
