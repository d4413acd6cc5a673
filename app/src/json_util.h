#pragma once
// Private helpers of kc::app for reading and writing JSON with messages that name the file and field.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <type_traits>

#include "kc/core/cage.h"
#include "kc/core/deform.h"
#include "kc/core/types.h"
#include "kc/app/structure.h"

namespace kc::app::detail {

using nlohmann::json;

/// "byte N, near '...<up to 32 bytes of text around N>...'": where a file went wrong, quoted with its
/// bytes outside printable ASCII as \xNN (the message stays one short line whatever the file holds).
std::string excerptAt(std::string_view text, std::size_t offset);
/// v as JSON text, cut to about 32 characters (with the full length) when longer: how messages
/// quote a value read from a file.
std::string quoted(const json& v);
/// Estimated memory, bytes, of text parsed into a json (a streaming count of its values, arrays,
/// objects, keys and string bytes), the count stopped once past `limit`.
double jsonParseCost(const std::string& text, double limit);
/// Parses text; a text of 4 MiB or more is first counted (jsonParseCost) and refused when its
/// parse would need more than kMaxJsonParseBytes, before anything is built. InputError "<where>: malformed JSON at byte N, near '...': <problem>" (truncated
/// files included); the message quotes at most excerptAt's excerpt of the text.
json parseJson(const std::string& text, const std::string& where);
/// Requires {"version": 1}; a missing or other major version is an InputError.
void checkVersion(const json& j, const std::string& where);
/// obj[key] when obj is an object holding a value of T's kind there (true/false for bool, a number
/// otherwise), else `fallback`: for the report blocks, whose missing or damaged entries read as
/// their defaults.
template <class T>
T valueOr(const json& obj, const char* key, T fallback) {
  if (!obj.is_object() || !obj.contains(key)) return fallback;
  const json& v = obj[key];
  if constexpr (std::is_same_v<T, bool>) return v.is_boolean() ? v.get<bool>() : fallback;
  else return v.is_number() ? v.get<T>() : fallback;
}
/// obj[key], InputError "<where>: missing key '<key>'" when absent.
const json& require(const json& obj, const char* key, const std::string& where);
/// A finite number; InputError naming `field` otherwise.
double finiteNumber(const json& v, const std::string& where, const std::string& field);
/// A finite number with |v| ≤ maxAbs; InputError naming `field` otherwise.
double boundedNumber(const json& v, double maxAbs, const std::string& where, const std::string& field);
/// A whole number in [lo, hi], checked before any conversion (no wrap-around); InputError naming
/// `field` otherwise.
long long integerInRange(const json& v, long long lo, long long hi, const std::string& where, const std::string& field);
/// [[x, y], ...] → #P×2; every coordinate finite with |x| ≤ kMaxCoordinate.
Points parsePoints(const json& arr, const std::string& where, const std::string& field);
json pointsToJson(const Points& P);

/// {"points": ..., "closed": ..., "edges"?: ...} → validated Cage.
Cage parseCage(const json& obj, const std::string& where, const std::string& field);
/// The same without the checks of the cage's shape (validateCage): a cage being drawn, which may
/// be open, short or crossing itself. Points (count, finite, bounded) and edge indices are checked.
Cage parseCageDraft(const json& obj, const std::string& where, const std::string& field);
json cageToJson(const Cage& cage);

/// {"positions": ...} or {"handles": ...} with exactly C.rows() entries.
Pose parsePose(const json& obj, const Points& C, const std::string& where, const std::string& field);
json poseToJson(const Pose& pose);

/// A structure file's or session's "lines" array → lines and parallel-group names (entries
/// named field[k]); null gives none.
Structure parseStructureLines(const json& arr, const std::string& where, const std::string& field);
/// A structure file's or session's "rigid" array → regions (entries named field[k]: "polygon" of
/// ≥ 3 finite points, optional "strength" in [0, 1], default 1); null gives none.
std::vector<RigidRegion> parseRigidRegions(const json& arr, const std::string& where, const std::string& field);
/// [{"polygon": [[x, y], ...], "strength": s}, ...] of the structure's regions.
json rigidToJson(const Structure& structure);
/// {"points": [[x0, y0], [x1, y1]], "parallel"?: name} of line k.
json lineToJson(const Structure& structure, std::size_t k);

}  // namespace kc::app::detail
