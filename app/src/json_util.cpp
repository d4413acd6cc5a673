#include "json_util.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kc/app/errors.h"
#include "kc/app/image_header.h"
#include "kc/app/limits.h"
#include "kc/app/text.h"

namespace kc::app::detail {

std::string excerptAt(std::string_view text, std::size_t offset) {
  constexpr std::size_t kBefore = 24, kAfter = 8;
  const std::size_t end = std::min(text.size(), offset + kAfter);
  const std::size_t begin = std::min(end, offset > kBefore ? offset - kBefore : 0);
  std::string quote;
  for (const char c : text.substr(begin, end - begin)) {  // printable ASCII as it is, any other byte as \xNN
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f && c != '\\') quote += c;
    else if (c == '\\') quote += "\\\\";
    else quote += format("\\x%02x", u);
  }
  return "byte " + std::to_string(offset) + ", near '" + std::string(begin > 0 ? "..." : "") + quote +
         (end < text.size() ? "..." : "") + "'";
}

std::string quoted(const json& v) {
  std::string text = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() <= 40) return text;
  std::size_t cut = 32;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return text.substr(0, cut) + "... (" + std::to_string(text.size()) + " characters)";
}

namespace {

/// Counts what a DOM parse of a text would build and estimates its memory (nlohmann::json: 16
/// bytes a value, twice that in an array that grew by doubling; a heap container per array and
/// object; a map node and the key per object member; a heap string per string), stopping as soon
/// as the estimate passes `limit`. A malformed text stops the scan; the DOM parse then reports it.
class ParseCost final : public nlohmann::json_sax<json> {
 public:
  explicit ParseCost(double limit) : m_limit(limit) {}
  double bytes() const { return m_bytes; }
  bool over() const { return m_bytes > m_limit; }

  bool null() override { return add(32); }
  bool boolean(bool) override { return add(32); }
  bool number_integer(number_integer_t) override { return add(32); }
  bool number_unsigned(number_unsigned_t) override { return add(32); }
  bool number_float(number_float_t, const string_t&) override { return add(32); }
  bool string(string_t& v) override { return add(64 + double(v.size())); }
  bool binary(binary_t& v) override { return add(64 + double(v.size())); }
  bool start_object(std::size_t) override { return add(80); }
  bool key(string_t& k) override { return add(96 + double(k.size())); }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return add(64); }
  bool end_array() override { return true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  bool add(double b) {
    m_bytes += b;
    return !over();
  }
  double m_limit, m_bytes = 0.0;
};

/// Texts this short cannot need kMaxJsonParseBytes parsed (at most ~100 bytes of DOM per byte).
constexpr std::size_t kParseScanFrom = 4 * kMiB;

/// What a file that is not JSON text is, by its bytes: "a PNG image" (any picture whose header
/// kcwarp reads, readImageHeader), "binary data" for a zero byte among the first 4 KiB (JSON text
/// never holds one), "" otherwise.
std::string binaryKind(std::string_view text) {
  ImageHeader header;
  if (std::string problem; readImageHeader(text, header, problem)) return "a " + header.format + " image";
  if (text.substr(0, 4096).find('\0') != std::string_view::npos) return "binary data";
  return "";
}

}  // namespace

double jsonParseCost(const std::string& text, double limit) {
  ParseCost cost(limit);
  json::sax_parse(text, &cost);
  return cost.bytes();
}

json parseJson(const std::string& text, const std::string& where) {
  if (const std::string kind = binaryKind(text); !kind.empty())
    throw InputError(where, "this file is " + kind + ", not JSON text (a cage, pose, structure or session file is .json)");
  if (text.size() >= kParseScanFrom) {
    if (jsonParseCost(text, kMaxJsonParseBytes) > kMaxJsonParseBytes)
      throw InputError(where, "parsing this file would need more than the " + byteText(kMaxJsonParseBytes) +
                                  " of memory kcwarp allows for one file (counted before parsing); it holds far more JSON values "
                                  "than any file kcwarp writes");
  }
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error
    // while parsing value - <problem>; last read: '<the token, any length>'; expected <token>".
    std::string what = e.what();
    const auto colon = what.find(": ", what.find("parse error"));
    std::string problem = colon == std::string::npos ? what : what.substr(colon + 2);
    if (const auto last = problem.find("; last read: '"); last != std::string::npos) {
      const auto expected = problem.rfind("'; expected ");
      problem = problem.substr(0, last) + (expected != std::string::npos && expected > last ? problem.substr(expected + 1) : "");
    }
    const std::size_t offset = e.byte > 0 ? std::min<std::size_t>(e.byte - 1, text.size()) : 0;
    std::string message = "malformed JSON at " + excerptAt(text, offset) + ": " + problem;
    if (e.byte >= text.size()) message += " (the file looks truncated)";
    throw InputError(where, message);
  } catch (const json::exception& e) {  // e.g. a number too large for a double (the message quotes it whole)
    std::string what = e.what();
    const auto p = what.find("] ");
    throw InputError(where, "malformed JSON: " + oneLine(p == std::string::npos ? what : what.substr(p + 2), 120));
  }
}

void checkVersion(const json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(where, "expected a JSON object at the top level");
  if (!j.contains("version")) throw InputError(where, "missing key 'version' (expected \"version\": 1)");
  const json& v = j["version"];
  if (!v.is_number_integer()) throw InputError(where, "'version' must be an integer");
  if (v.get<long long>() != 1)
    throw InputError(where, "unsupported version " + std::to_string(v.get<long long>()) + " (this kcwarp reads version 1)");
}

const json& require(const json& obj, const char* key, const std::string& where) {
  if (!obj.is_object() || !obj.contains(key)) throw InputError(where, std::string("missing key '") + key + "'");
  return obj[key];
}

double finiteNumber(const json& v, const std::string& where, const std::string& field) {
  if (!v.is_number()) throw InputError(where, field + " must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw InputError(where, field + " is not finite");
  return d;
}

double boundedNumber(const json& v, double maxAbs, const std::string& where, const std::string& field) {
  const double d = finiteNumber(v, where, field);
  if (!(std::abs(d) <= maxAbs))
    throw InputError(where, field + " = " + quoted(v) + " is out of range (|value| ≤ " + json(maxAbs).dump() + ")");
  return d;
}

long long integerInRange(const json& v, long long lo, long long hi, const std::string& where, const std::string& field) {
  const std::string range = " (" + std::to_string(lo) + ".." + std::to_string(hi) + ")";
  if (!v.is_number_integer()) throw InputError(where, field + " must be a whole number" + range);
  const bool ok = v.is_number_unsigned() ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::max(hi, 0LL)) &&
                                               static_cast<long long>(v.get<std::uint64_t>()) >= lo
                                         : v.get<std::int64_t>() >= lo && v.get<std::int64_t>() <= hi;
  if (!ok) throw InputError(where, field + " = " + quoted(v) + " is out of range" + range);
  return v.is_number_unsigned() ? static_cast<long long>(v.get<std::uint64_t>()) : static_cast<long long>(v.get<std::int64_t>());
}

Points parsePoints(const json& arr, const std::string& where, const std::string& field) {
  if (!arr.is_array()) throw InputError(where, field + " must be an array of [x, y] pairs");
  Points P(static_cast<Index>(arr.size()), 2);
  for (std::size_t i = 0; i < arr.size(); ++i) {
    const json& p = arr[i];
    const std::string f = field + "[" + std::to_string(i) + "]";
    if (!p.is_array() || p.size() != 2) throw InputError(where, f + " must be a pair [x, y]");
    P(static_cast<Index>(i), 0) = boundedNumber(p[0], kMaxCoordinate, where, f + "[0]");
    P(static_cast<Index>(i), 1) = boundedNumber(p[1], kMaxCoordinate, where, f + "[1]");
  }
  return P;
}

json pointsToJson(const Points& P) {
  json arr = json::array();
  for (Index i = 0; i < P.rows(); ++i) arr.push_back({P(i, 0), P(i, 1)});
  return arr;
}

Cage parseCageDraft(const json& obj, const std::string& where, const std::string& field) {
  const std::string pre = field.empty() ? "" : field + ".";
  Cage cage;
  const json& points = require(obj, "points", where);
  if (points.is_array() && points.size() > static_cast<std::size_t>(kMaxCagePoints))
    throw InputError(where, pre + "points has " + std::to_string(points.size()) + " points, more than kcwarp's limit of " +
                                std::to_string(kMaxCagePoints));
  cage.C = parsePoints(points, where, pre + "points");
  cage.closed = true;
  if (obj.contains("closed")) {
    if (!obj["closed"].is_boolean()) throw InputError(where, pre + "closed must be true or false");
    cage.closed = obj["closed"].get<bool>();
  }
  if (obj.contains("edges") && !obj["edges"].is_null()) {
    const json& e = obj["edges"];
    if (!e.is_array()) throw InputError(where, pre + "edges must be an array of [i, j] pairs");
    if (e.size() > 4 * static_cast<std::size_t>(kMaxCagePoints))
      throw InputError(where, pre + "edges has " + std::to_string(e.size()) + " edges, more than kcwarp's limit of " +
                                  std::to_string(4 * kMaxCagePoints));
    const long long last = static_cast<long long>(cage.C.rows()) - 1;
    for (std::size_t k = 0; k < e.size(); ++k) {
      const std::string f = pre + "edges[" + std::to_string(k) + "]";
      if (!e[k].is_array() || e[k].size() != 2) throw InputError(where, f + " must be a pair of point indices");
      const auto a = static_cast<int>(integerInRange(e[k][0], 0, last, where, f + "[0]"));
      const auto b = static_cast<int>(integerInRange(e[k][1], 0, last, where, f + "[1]"));
      cage.edges.push_back({a, b});
    }
  } else if (cage.closed) {
    cage = Cage::polygon(cage.C);
  } else {
    for (int i = 0; i + 1 < static_cast<int>(cage.C.rows()); ++i) cage.edges.push_back({i, i + 1});
  }
  return cage;
}

Cage parseCage(const json& obj, const std::string& where, const std::string& field) {
  Cage cage = parseCageDraft(obj, where, field);
  try {
    validateCage(cage);
  } catch (const std::invalid_argument& e) {
    throw InputError(where, e.what());
  }
  return cage;
}

json cageToJson(const Cage& cage) {
  json j = {{"points", pointsToJson(cage.C)}, {"closed", cage.closed}};
  const Cage poly = Cage::polygon(cage.C);
  if (!cage.closed || cage.edges != poly.edges) {
    json e = json::array();
    for (const auto& [a, b] : cage.edges) e.push_back({a, b});
    j["edges"] = e;
  }
  return j;
}

Pose parsePose(const json& obj, const Points& C, const std::string& where, const std::string& field) {
  const std::string pre = field.empty() ? "" : field + ".";
  const Index m = C.rows();
  auto countError = [&](std::size_t n, const char* key) {
    return InputError(where, pre + key + " has " + std::to_string(n) + " entries but the cage has " + std::to_string(m) +
                                 " control points");
  };
  Pose pose(static_cast<std::size_t>(m));
  if (obj.contains("positions")) {
    const Points P = parsePoints(obj["positions"], where, pre + "positions");
    if (P.rows() != m) throw countError(static_cast<std::size_t>(P.rows()), "positions");
    return asUserInput(where, [&] { return poseFromPositions(C, P); });
  }
  if (!obj.contains("handles")) throw InputError(where, "missing key '" + pre + "positions' or '" + pre + "handles'");
  const json& h = obj["handles"];
  if (!h.is_array()) throw InputError(where, pre + "handles must be an array");
  if (static_cast<Index>(h.size()) != m) throw countError(h.size(), "handles");
  for (std::size_t i = 0; i < h.size(); ++i) {
    const std::string f = pre + "handles[" + std::to_string(i) + "]";
    if (!h[i].is_object()) throw InputError(where, f + " must be an object {\"translate\": [dx, dy], \"rotate\": r}");
    HandlePose& p = pose[i];
    if (h[i].contains("translate")) {
      const json& t = h[i]["translate"];
      if (!t.is_array() || t.size() != 2) throw InputError(where, f + ".translate must be a pair [dx, dy]");
      p.translate = Vec2(boundedNumber(t[0], kMaxCoordinate, where, f + ".translate[0]"),
                         boundedNumber(t[1], kMaxCoordinate, where, f + ".translate[1]"));
    }
    if (h[i].contains("rotate")) p.rotate = boundedNumber(h[i]["rotate"], kMaxRotation, where, f + ".rotate");
  }
  return pose;
}

json poseToJson(const Pose& pose) {
  json h = json::array();
  for (const HandlePose& p : pose) h.push_back({{"translate", {p.translate.x(), p.translate.y()}}, {"rotate", p.rotate}});
  return {{"handles", h}};
}

}  // namespace kc::app::detail
