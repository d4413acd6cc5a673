#include <algorithm>

#include "json_util.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/limits.h"
#include "kc/app/structure.h"

namespace kc::app {
namespace detail {
namespace {

/// Calls each(entry, "field[k]") for the objects of the structure file's array `arr` (null: no
/// entries), after checking it is an array of at most kMaxCagePoints objects shaped like `shape`;
/// `noun` counts them in the message ("lines", "regions").
template <class F>
void forEachEntry(const json& arr, const std::string& where, const std::string& field, const char* noun,
                  const std::string& shape, F&& each) {
  if (arr.is_null()) return;
  if (!arr.is_array()) throw InputError(where, field + " must be an array of " + shape + " entries");
  if (arr.size() > static_cast<std::size_t>(kMaxCagePoints))
    throw InputError(where, field + " has " + std::to_string(arr.size()) + " " + noun + ", more than kcwarp's limit of " +
                                std::to_string(kMaxCagePoints));
  for (std::size_t k = 0; k < arr.size(); ++k) {
    const std::string f = field + "[" + std::to_string(k) + "]";
    if (!arr[k].is_object()) throw InputError(where, f + " must be an object " + shape);
    each(arr[k], f);
  }
}

}  // namespace

Structure parseStructureLines(const json& arr, const std::string& where, const std::string& field) {
  Structure st;
  forEachEntry(arr, where, field, "lines", "{\"points\": [[x0, y0], [x1, y1]]}", [&](const json& e, const std::string& f) {
    const json& pts = require(e, "points", where);
    if (!pts.is_array() || pts.size() != 2) throw InputError(where, f + ".points must be two points [[x0, y0], [x1, y1]]");
    const Points P = parsePoints(pts, where, f + ".points");
    StructureLine l;
    l.a = P.row(0).transpose();
    l.b = P.row(1).transpose();
    if (e.contains("parallel") && !e["parallel"].is_null()) {
      if (!e["parallel"].is_string() || e["parallel"].get<std::string>().empty())
        throw InputError(where, f + ".parallel must be a group name (a non-empty string)");
      const std::string name = e["parallel"].get<std::string>();
      auto it = std::find(st.groups.begin(), st.groups.end(), name);
      l.group = static_cast<int>(it - st.groups.begin());
      if (it == st.groups.end()) st.groups.push_back(name);
    }
    st.lines.push_back(l);
  });
  return st;
}

std::vector<RigidRegion> parseRigidRegions(const json& arr, const std::string& where, const std::string& field) {
  std::vector<RigidRegion> out;
  forEachEntry(arr, where, field, "regions", "{\"polygon\": [[x, y], ...], \"strength\": s}", [&](const json& e, const std::string& f) {
    const json& pts = require(e, "polygon", where);
    if (!pts.is_array() || pts.size() < 3) throw InputError(where, f + ".polygon must be at least 3 points [[x, y], ...]");
    if (pts.size() > static_cast<std::size_t>(kMaxCagePoints))
      throw InputError(where, f + ".polygon has more than " + std::to_string(kMaxCagePoints) + " points");
    RigidRegion r;
    r.polygon = parsePoints(pts, where, f + ".polygon");
    if (e.contains("strength") && !e["strength"].is_null()) {
      const json& s = e["strength"];
      if (!s.is_number() || !(s.get<double>() >= 0.0 && s.get<double>() <= 1.0))
        throw InputError(where, f + ".strength must be a number in [0, 1] (got " + quoted(s) + ")");
      r.strength = s.get<double>();
    }
    out.push_back(std::move(r));
  });
  return out;
}

json lineToJson(const Structure& st, std::size_t k) {
  const StructureLine& l = st.lines[k];
  json e = {{"points", {{l.a.x(), l.a.y()}, {l.b.x(), l.b.y()}}}};
  if (l.group >= 0) e["parallel"] = st.groups[static_cast<std::size_t>(l.group)];
  return e;
}

json rigidToJson(const Structure& st) {
  json arr = json::array();
  for (const RigidRegion& r : st.rigid) {
    json poly = json::array();
    for (Index i = 0; i < r.polygon.rows(); ++i) poly.push_back({r.polygon(i, 0), r.polygon(i, 1)});
    arr.push_back({{"polygon", poly}, {"strength", r.strength}});
  }
  return arr;
}

}  // namespace detail

std::string structureToJson(const Structure& structure) {
  detail::json lines = detail::json::array();
  for (std::size_t k = 0; k < structure.lines.size(); ++k) lines.push_back(detail::lineToJson(structure, k));
  detail::json j = {{"version", 1}, {"lines", lines}};
  if (!structure.rigid.empty()) j["rigid"] = detail::rigidToJson(structure);
  return j.dump() + "\n";
}

Structure structureFromJson(const std::string& text, const std::string& where) {
  const detail::json j = detail::parseJson(text, where);
  detail::checkVersion(j, where);
  Structure st = j.contains("lines") ? detail::parseStructureLines(j["lines"], where, "lines") : Structure{};
  if (j.contains("rigid")) st.rigid = detail::parseRigidRegions(j["rigid"], where, "rigid");
  return st;
}

Structure loadStructure(const std::string& path) { return structureFromJson(readTextFile(path), path); }

void checkStructure(const Structure& structure, const Cage& cage, double h, const std::string& where, bool graded) {
  asUserInput(where, [&] {
    validateLines(cage, structure.lines, h, graded);
    validateRigidRegions(cage, structure.rigid);
  });
}

}  // namespace kc::app
