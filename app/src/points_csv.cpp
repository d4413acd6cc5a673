#include "kc/app/points_csv.h"

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <utility>
#include <vector>

#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/limits.h"

namespace kc::app {
namespace {

enum class Field { Number, NotNumber, Malformed };

/// A field "  12.5 " → Number (v set, finite and in range); text that does not start like a
/// number → NotNumber; anything else (trailing junk, nan, inf, out of range) → Malformed.
Field parseField(const char* begin, const char* end, double& v) {
  while (begin < end && (*begin == ' ' || *begin == '\t')) ++begin;
  while (end > begin && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r')) --end;
  if (begin == end) return Field::NotNumber;
  const std::string text(begin, end);
  char* stop = nullptr;
  v = std::strtod(text.c_str(), &stop);
  if (stop == text.c_str()) return Field::NotNumber;
  if (*stop != '\0' || !std::isfinite(v) || !(std::abs(v) <= kMaxCoordinate)) return Field::Malformed;
  return Field::Number;
}

}  // namespace

Points parsePointsCsv(const std::string& text, const std::string& where) {
  std::vector<double> xy;
  std::size_t begin = 0;
  long lineNo = 0;
  bool first = true;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    ++lineNo;
    const char* a = text.data() + begin;
    const char* b = text.data() + end;
    begin = end + 1;
    if (std::string_view(a, std::size_t(b - a)).find_first_not_of(" \t\r") == std::string_view::npos) continue;
    const char* comma = static_cast<const char*>(std::memchr(a, ',', std::size_t(b - a)));
    double x = 0, y = 0;
    const Field fx = comma ? parseField(a, comma, x) : Field::Malformed;
    const Field fy = comma ? parseField(comma + 1, b, y) : Field::Malformed;
    const bool isFirst = std::exchange(first, false);
    if (fx == Field::Number && fy == Field::Number) {
      xy.push_back(x);
      xy.push_back(y);
      continue;
    }
    if (isFirst && fx == Field::NotNumber && fy == Field::NotNumber) continue;  // a header such as "x,y"
    std::string shown(a, std::size_t(std::min<std::ptrdiff_t>(b - a, 80)));
    if (!shown.empty() && shown.back() == '\r') shown.pop_back();
    throw InputError(where, "line " + std::to_string(lineNo) + ": expected two finite numbers \"x,y\" (|x| ≤ 1e7), got '" +
                                shown + "'");
  }
  if (xy.empty()) throw InputError(where, "no points (expected rows \"x,y\")");
  Points P(static_cast<Index>(xy.size() / 2), 2);
  for (Index i = 0; i < P.rows(); ++i) P.row(i) << xy[std::size_t(2 * i)], xy[std::size_t(2 * i + 1)];
  return P;
}

Points loadPointsCsv(const std::string& path) { return parsePointsCsv(readTextFile(path, kMaxPointsFileBytes), path); }

}  // namespace kc::app
