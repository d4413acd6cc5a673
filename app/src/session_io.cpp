#include <algorithm>
#include <cmath>

#include "json_util.h"
#include "session_blocks.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/limits.h"
#include "kc/app/pipeline.h"
#include "kc/core/kernel/gaussian_kernel.h"
#include "kc/core/warp_mesh.h"

namespace kc::app {
namespace {

using detail::json;
using detail::getWeights;
using detail::putWeights;

template <NamedEnum E>
E parseEnum(const json& params, const char* key, E fallback, const std::string& where) {
  if (!params.contains(key)) return fallback;
  const json& v = params[key];
  E e{};
  if (!v.is_string() || !parseName(v.get<std::string>(), e))
    throw InputError(where, std::string("params.") + key + " has an unknown value " + detail::quoted(v));
  return e;
}

json samplesToJson(const SampleSet& S) {
  json kinds = json::array(), ends = json::array();
  for (Index i = 0; i < S.size(); ++i) {
    kinds.push_back(std::string(kc::toString(S.kind[static_cast<std::size_t>(i)])));
    ends.push_back({S.edge(i, 0), S.edge(i, 1)});
  }
  return {{"points", detail::pointsToJson(S.X)}, {"kinds", kinds}, {"edge_ends", ends}};
}

/// Refuses a session whose kernel matrix would exceed the bind limits (a σ far wider than the
/// samples' spacing makes K dense) before it is assembled.
void checkFieldCost(const Session& s, const std::string& where) {
  const Points& X = s.samples.X;
  const double n = static_cast<double>(X.rows());
  const double area = std::max((X.col(0).maxCoeff() - X.col(0).minCoeff()) * (X.col(1).maxCoeff() - X.col(1).minCoeff()), 1.0);
  const double cutoff = GaussianKernel::forSpacing(s.sigma, s.params.spacing).cutoff();
  const double nonZeros = n * std::min(n, 1.0 + n * 3.141592653589793 * cutoff * cutoff / area);
  if (nonZeros > double(kMaxKernelNonZeros))
    throw InputError(where, "params.sigma " + json(s.sigma).dump() + " px over these " + std::to_string(X.rows()) +
                                " samples gives a kernel matrix of about " + json(std::round(nonZeros)).dump() +
                                " non-zeros, above kcwarp's limit of " + std::to_string(kMaxKernelNonZeros));
}

}  // namespace

std::string samplesText(const SampleSet& samples, const std::string& extraJsonObject) {
  json j = {{"version", 1}};
  j.update(detail::parseJson(extraJsonObject, "saveSamples"));
  j["samples"] = samplesToJson(samples);
  if (!samples.lines.empty()) j["samples"]["lines"] = samples.lines;  // each structure line's samples, a → b
  return j.dump() + "\n";
}

void saveSamples(const std::string& path, const SampleSet& samples, const std::string& extraJsonObject) {
  writeFileAtomic(path, samplesText(samples, extraJsonObject));
}

/// The session's lines: the structure file's entries plus "samples" (their sample indices).
static json linesToJson(const Session& s) {
  json arr = json::array();
  for (std::size_t k = 0; k < s.structure.lines.size(); ++k) {
    json e = detail::lineToJson(s.structure, k);
    if (k < s.samples.lines.size()) e["samples"] = s.samples.lines[k];
    arr.push_back(e);
  }
  return arr;
}

namespace {

/// Reads `backend`'s stored parameters from params.<block> (the top of params for a backend
/// without a block): a key the file lacks takes its absentValue when it has one, else keeps its
/// default. Then the backend's own readParameters.
void parametersFromJson(const Backend& backend, const json& params, Session& s, const std::string& where) {
  const std::string block(backend.parameterBlock());
  const std::string prefix = "params." + (block.empty() ? "" : block + ".");
  static const json none = json::object();
  const json& values = block.empty() ? params : params.contains(block) ? params[block] : none;
  if (!values.is_object()) throw InputError(where, "params." + block + " must be an object");
  for (const BackendParameter& parameter : backend.parameters()) {
    if (!parameter.stored) continue;
    const std::string what = prefix + parameter.key;
    std::optional<double> value = parameter.absentValue;
    if (values.contains(parameter.key)) {
      const json& v = values[parameter.key];
      switch (parameter.type) {
        case BackendParameter::Type::Choice:
          value = v.is_string() ? parseParameter(parameter, v.get<std::string>()) : std::nullopt;
          if (!value)
            throw InputError(where, what + " has an unknown value " + detail::quoted(v) + " (" + parameterRange(parameter) + ")");
          break;
        case BackendParameter::Type::Boolean:
          if (!v.is_boolean()) throw InputError(where, what + " must be true or false");
          value = v.get<bool>() ? 1.0 : 0.0;
          break;
        case BackendParameter::Type::Integer:
        case BackendParameter::Type::Number:
          value = detail::finiteNumber(v, where, what);
          break;
      }
    }
    if (!value) continue;
    try {
      setParameter(backend, parameter, s.params, *value);
    } catch (const std::invalid_argument& e) {
      throw InputError(where, what + " " + e.what());
    }
  }
  backend.readParameters(params, s, where);
}

}  // namespace

std::string sessionToJson(const Session& s, WeightsForm form) {
  const BindParams& p = s.params;
  json params = {{"spacing", p.spacing}, {"sigma", s.sigma},
                 {"backend", p.backend}, {"sampler", std::string(toString(p.sampler))},
                 {"margin", p.margin},   {"exterior", std::string(toString(p.exterior))},
                 {"seed", p.seed},       {"graded", p.graded}};
  if (s.lbcMeshSpacing > 0.0) params["lbc_mesh_spacing"] = s.lbcMeshSpacing;
  // Every backend's parameters, the bound one's and the others' (the next bind may switch).
  for (const std::string_view name : backendNames()) {
    const Backend& backend = backendFor(name);
    if (const std::string block(backend.parameterBlock()); !block.empty()) params[block] = parametersToJson(backend, p);
    else params.update(parametersToJson(backend, p));
    backend.writeParameters(s, params);
  }
  json j = {{"version", 1},
            {"cage", detail::cageToJson(s.cage)},
            {"image_size", {s.imageWidth, s.imageHeight}},
            {"params", params},
            {"samples", samplesToJson(s.samples)},
            {"weights", json::object()},
            {"lines", linesToJson(s)},
            {"rigid", detail::rigidToJson(s.structure)},
            {"image", s.image}};
  if (s.imageUpright) j["image_upright"] = true;  // absent: the picture as stored (older sessions)
  putWeights(j["weights"], "optimized", s.W, form);
  if (s.W0.rows() > 0) putWeights(j["weights"], "initial", s.W0, form);  // a backend without targets has none
  if (s.sizing && s.sizing->graded()) {
    json seeds = json::array();
    const Eigen::VectorXd& slopes = s.sizing->slopes();  // a seed's own slope as a 4th entry where it differs
    for (Index i = 0; i < s.sizing->seeds().rows(); ++i) {
      json seed = {s.sizing->seeds()(i, 0), s.sizing->seeds()(i, 1), s.sizing->sizes()(i)};
      if (slopes.size() > 0 && slopes(i) != s.sizing->gradation()) seed.push_back(slopes(i));
      seeds.push_back(std::move(seed));
    }
    j["sizing"] = {{"gradation", s.sizing->gradation()}, {"seeds", seeds}};
    if (s.sizing->form() == SizingForm::Smooth) j["sizing"]["form"] = "smooth";
  }
  if (const json field = detail::fieldToJson(s, form); !field.is_null()) j["field"] = field;
  j["reports"] = detail::reportsToJson(s.report, backendFor(s.params.backend));
  if (s.hasRigidity()) {
    json idx = json::array(), rho = json::array();
    for (std::size_t i = 0; i < s.rigidity.size(); ++i)
      if (s.rigidity[i] > 0.0) idx.push_back(i), rho.push_back(s.rigidity[i]);
    j["rigidity"] = {{"samples", idx}, {"rho", rho}};
  }
  if (!s.pose.empty()) j["pose"] = detail::poseToJson(s.pose);
  if (s.outside) j["outside"] = std::string(toString(*s.outside));
  const BindTimings& t = s.report.timings;
  j["timings"] = {{"sampling", t.sampling}, {"assemble", t.assemble}, {"factor", t.factor}, {"init", t.init},
                  {"optimize", t.optimize}, {"solve", t.solve},       {"total", t.total}};
  return j.dump() + "\n";
}

/// The `sizing` block: {"gradation": g, "seeds": [[x, y, h] or [x, y, h, g_i], ...], "form": "smooth"}
/// with hMax = params.spacing; g_i is the seed's cone's slope where it is not g (SizingField); without
/// "form" (sessions written before the smooth form) the cones' minimum.
static std::shared_ptr<const SizingField> sizingFromJson(const json& block, double hMax, const std::string& where) {
  if (!block.is_object()) throw InputError(where, "sizing must be an object");
  const double g = detail::boundedNumber(detail::require(block, "gradation", where), 1.0, where, "sizing.gradation");
  const json& seeds = detail::require(block, "seeds", where);
  if (!seeds.is_array()) throw InputError(where, "sizing.seeds must be an array of [x, y, h]");
  if (seeds.size() > std::size_t(sampling::kMaxSamples))
    throw InputError(where, "sizing.seeds has " + std::to_string(seeds.size()) + " entries, more than " + std::to_string(sampling::kMaxSamples));
  SizingForm form = SizingForm::Min;
  if (block.contains("form")) {
    if (block["form"] != "smooth" && block["form"] != "min") throw InputError(where, "sizing.form must be \"smooth\" or \"min\"");
    form = block["form"] == "smooth" ? SizingForm::Smooth : SizingForm::Min;
  }
  Points P(Index(seeds.size()), 2);
  Eigen::VectorXd H(Index(seeds.size())), G = Eigen::VectorXd::Constant(Index(seeds.size()), g);
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    const json& e = seeds[i];
    const std::string name = "sizing.seeds[" + std::to_string(i) + "]";
    if (!e.is_array() || (e.size() != 3 && e.size() != 4))
      throw InputError(where, name + " must be [x, y, h] or [x, y, h, slope]");
    P(Index(i), 0) = detail::boundedNumber(e[0], kMaxCoordinate, where, name);
    P(Index(i), 1) = detail::boundedNumber(e[1], kMaxCoordinate, where, name);
    H(Index(i)) = detail::boundedNumber(e[2], kMaxCoordinate, where, name);
    if (e.size() == 4) G(Index(i)) = detail::boundedNumber(e[3], 1.0, where, name);
  }
  try {
    return std::make_shared<const SizingField>(hMax, g, P, H, form, G);
  } catch (const std::invalid_argument& e) {
    throw InputError(where, std::string("sizing: ") + e.what());
  }
}

namespace {

/// The session's `params` block into s.params, with σ (s.sigma) and the LBC mesh spacing
/// (s.lbcMeshSpacing); absent keys take the meaning they had before the key existed.
void paramsFromJson(const json& params, Session& s, const std::string& where) {
  if (!params.is_object()) throw InputError(where, "params must be an object");
  BindParams& p = s.params;
  p.spacing = detail::boundedNumber(detail::require(params, "spacing", where), kMaxCoordinate, where, "params.spacing");
  if (!(p.spacing > 0)) throw InputError(where, "params.spacing must be positive");
  if (params.contains("backend")) {
    if (!params["backend"].is_string()) throw InputError(where, "params.backend must be a name");
    p.backend = params["backend"].get<std::string>();
    asUserInput(where, [&] { backendFor(p.backend); });
  }
  const bool kernel = backendFor(p.backend).capabilities().targets;  // σ belongs to the kernel backend
  s.sigma = kernel || params.contains("sigma")
                ? detail::boundedNumber(detail::require(params, "sigma", where), kMaxCoordinate, where, "params.sigma")
                : 0.0;
  if (kernel && !(s.sigma > 0)) throw InputError(where, "params.sigma must be positive");
  for (const std::string_view name : backendNames()) parametersFromJson(backendFor(name), params, s, where);
  p.sampler = parseEnum(params, "sampler", sampling::SamplerKind::BlueNoise, where);
  p.exterior = parseEnum(params, "exterior", sampling::ExteriorExtent::Frame, where);  // older sessions sampled the frame
  if (params.contains("lbc_mesh_spacing")) {
    s.lbcMeshSpacing = detail::boundedNumber(params["lbc_mesh_spacing"], kMaxCoordinate, where, "params.lbc_mesh_spacing");
    if (!(s.lbcMeshSpacing > 0.0)) throw InputError(where, "params.lbc_mesh_spacing must be a positive number of pixels");
  } else if (backendFor(p.backend).weightSpacing(p) != p.spacing) {  // the kc backend's LBC targets
    s.lbcMeshSpacing = p.spacing;  // written before the samples were made denser than the LBC mesh: the mesh was at h
  }
  if (params.contains("margin")) p.margin = detail::boundedNumber(params["margin"], kMaxCoordinate, where, "params.margin");
  p.graded = false;  // sessions written before graded sampling were sampled uniformly
  if (params.contains("graded")) {
    if (!params["graded"].is_boolean()) throw InputError(where, "params.graded must be true or false");
    p.graded = params["graded"].get<bool>();
  }
  if (params.contains("seed")) {
    if (!params["seed"].is_number_unsigned()) throw InputError(where, "params.seed must be a whole number ≥ 0");
    p.seed = params["seed"].get<std::uint64_t>();
  }
}

/// The samples (points, kinds, edge ends), the structure lines with their samples, the rigid
/// regions and ρ; checks them against the cage (s.cage).
void samplesFromJson(const json& j, Session& s, const std::string& where) {
  const Index m = s.cage.size();
  const json& samples = detail::require(j, "samples", where);
  if (const json& pts = detail::require(samples, "points", where); pts.is_array() && pts.size() > std::size_t(sampling::kMaxSamples))
    throw InputError(where, "samples.points has " + std::to_string(pts.size()) + " samples, more than kcwarp's limit of " +
                                std::to_string(sampling::kMaxSamples));
  s.samples.X = detail::parsePoints(detail::require(samples, "points", where), where, "samples.points");
  const Index n = s.samples.X.rows();
  const json& kinds = detail::require(samples, "kinds", where);
  if (!kinds.is_array() || static_cast<Index>(kinds.size()) != n)
    throw InputError(where, "samples.kinds must have one entry per sample (" + std::to_string(n) + ")");
  s.samples.kind.resize(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    const json& k = kinds[static_cast<std::size_t>(i)];
    if (!k.is_string() || !parseName(k.get<std::string>(), s.samples.kind[static_cast<std::size_t>(i)]))
      throw InputError(where, "samples.kinds[" + std::to_string(i) + "] is not one of control, edge, line, interior, exterior");
  }
  s.samples.edge.setConstant(n, 2, -1);
  if (samples.contains("edge_ends")) {
    const json& e = samples["edge_ends"];
    if (!e.is_array() || static_cast<Index>(e.size()) != n)
      throw InputError(where, "samples.edge_ends must have one [k, l] pair per sample");
    for (Index i = 0; i < n; ++i) {
      const json& r = e[static_cast<std::size_t>(i)];
      const std::string f = "samples.edge_ends[" + std::to_string(i) + "]";
      if (!r.is_array() || r.size() != 2) throw InputError(where, f + " must be a pair of integers");
      s.samples.edge(i, 0) = static_cast<int>(detail::integerInRange(r[0], -1, m - 1, where, f + "[0]"));
      s.samples.edge(i, 1) = static_cast<int>(detail::integerInRange(r[1], -1, m - 1, where, f + "[1]"));
    }
  }
  if (j.contains("lines")) {
    s.structure = detail::parseStructureLines(j["lines"], where, "lines");
    for (std::size_t k = 0; k < s.structure.lines.size(); ++k) {
      const std::string f = "lines[" + std::to_string(k) + "].samples";
      if (s.params.kc.exactLines && !j["lines"][k].contains("samples")) continue;  // the field's correction: no line samples
      const json& idx = detail::require(j["lines"][k], "samples", where);
      if (!idx.is_array() || idx.size() < 2) throw InputError(where, f + " must list the line's sample indices (at least two)");
      std::vector<Index> v;
      for (std::size_t q = 0; q < idx.size(); ++q)
        v.push_back(static_cast<Index>(detail::integerInRange(idx[q], 0, n - 1, where, f + "[" + std::to_string(q) + "]")));
      s.samples.lines.push_back(std::move(v));
    }
  }
  if (j.contains("rigid")) s.structure.rigid = detail::parseRigidRegions(j["rigid"], where, "rigid");
  if (j.contains("rigidity") && !j["rigidity"].is_null()) {
    const json& r = j["rigidity"];
    if (!r.is_object()) throw InputError(where, "rigidity must be {\"samples\": [i, ...], \"rho\": [r, ...]}");
    const json& idx = detail::require(r, "samples", where);
    const json& rho = detail::require(r, "rho", where);
    if (!idx.is_array() || !rho.is_array() || idx.size() != rho.size())
      throw InputError(where, "rigidity.samples and rigidity.rho must be arrays of the same length");
    s.rigidity.assign(static_cast<std::size_t>(n), 0.0);
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const std::string f = "rigidity.rho[" + std::to_string(k) + "]";
      const Index i = static_cast<Index>(detail::integerInRange(idx[k], 0, n - 1, where, "rigidity.samples[" + std::to_string(k) + "]"));
      if (!rho[k].is_number() || !(rho[k].get<double>() >= 0.0 && rho[k].get<double>() <= 1.0))
        throw InputError(where, f + " must be a number in [0, 1]");
      s.rigidity[std::size_t(i)] = rho[k].get<double>();
    }
  } else if (!s.structure.rigid.empty()) {
    s.rigidity = rigidityOfRegions(s.samples.X, s.structure.rigid);  // older writers: ρ from the polygons
  }
  try {
    s.samples.validate(m);
  } catch (const std::invalid_argument& e) {
    throw InputError(where, e.what());
  }
  for (Index i = 0; i < m; ++i)
    if ((s.samples.X.row(i) - s.cage.C.row(i)).norm() > 1e-9 * (1.0 + s.cage.C.row(i).norm()))
      throw InputError(where, "samples.points[" + std::to_string(i) + "] differs from cage point " + std::to_string(i) +
                                  " (the first samples must be the control points)");
}

/// The field: a self-contained block (mesh, or a registered codec's that builds it) is read as it
/// is, the others rebuilt by the backend.
void fieldOfSession(const json& j, Session& s, const std::string& where) {
  const bool built = j.contains("field") && detail::fieldFromJson(j["field"], s, where);
  if (!built) {
    if (s.sigma > 0) checkFieldCost(s, where);  // a kernel field is rebuilt from the samples
    try {
      refreshField(s);
    } catch (const std::invalid_argument& e) {
      throw InputError(where, e.what());
    }
  }
}

}  // namespace

Session sessionFromJson(const std::string& text, const std::string& where) {
  const json j = detail::parseJson(text, where);
  detail::checkVersion(j, where);
  Session s;
  s.cage = detail::parseCage(detail::require(j, "cage", where), where, "cage");
  const Index m = s.cage.size();

  if (j.contains("image_size")) {
    const json& sz = j["image_size"];
    if (!sz.is_array() || sz.size() != 2) throw InputError(where, "image_size must be [width, height] in whole pixels");
    s.imageWidth = static_cast<int>(detail::integerInRange(sz[0], 1, kMaxImageSide, where, "image_size[0]"));
    s.imageHeight = static_cast<int>(detail::integerInRange(sz[1], 1, kMaxImageSide, where, "image_size[1]"));
    checkImageSize(s.imageWidth, s.imageHeight, where, "image_size");
  }

  paramsFromJson(detail::require(j, "params", where), s, where);
  samplesFromJson(j, s, where);
  const Index n = s.samples.size();

  const json& weights = detail::require(j, "weights", where);
  if (!weights.is_object()) throw InputError(where, "weights must be an object");
  if (weights.contains("initial") || weights.contains("initial_b64"))
    s.W0 = getWeights(weights, "initial", n, m, where, "weights.initial");
  s.W = getWeights(weights, "optimized", n, m, where, "weights.optimized");
  detail::checkWeightRows(s.W, s.samples.X, s.cage.C, where, "weights.optimized");
  if (j.contains("pose") && !j["pose"].is_null()) s.pose = detail::parsePose(j["pose"], s.cage.C, where, "pose");
  if (j.contains("image")) {
    if (!j["image"].is_string()) throw InputError(where, "image must be a path string");
    s.image = j["image"].get<std::string>();
  }
  s.imageUpright = false;
  if (j.contains("image_upright")) {
    if (!j["image_upright"].is_boolean()) throw InputError(where, "image_upright must be true or false");
    s.imageUpright = j["image_upright"].get<bool>();
  }
  if (j.contains("outside") && !j["outside"].is_null()) {
    OutsideMode mode;
    if (!j["outside"].is_string() || !parseName(j["outside"].get<std::string>(), mode))
      throw InputError(where, "outside must be one of " + nameList<OutsideMode>());
    s.outside = mode;
  }
  if (j.contains("reports")) s.report = detail::reportsFromJson(j["reports"], backendFor(s.params.backend));
  if (j.contains("timings") && j["timings"].is_object()) {
    const json& t = j["timings"];
    auto get = [&](const char* k) { return detail::valueOr(t, k, 0.0); };
    s.report.timings = {get("sampling"), get("assemble"), get("factor"), get("init"),
                        get("optimize"), get("solve"),    get("total")};
  }
  if (j.contains("sizing") && !j["sizing"].is_null()) s.sizing = sizingFromJson(j["sizing"], s.params.spacing, where);
  fieldOfSession(j, s, where);
  return s;
}

Session loadSession(const std::string& path) { return sessionFromJson(readTextFile(path, kMaxSessionFileBytes), path); }

void saveSession(const std::string& path, const Session& session) { writeFileAtomic(path, sessionToJson(session)); }

}  // namespace kc::app
