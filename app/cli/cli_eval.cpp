// kcwarp-cli eval: weights of a session at arbitrary points.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"

namespace kc::cli {
namespace {

bool parseNumber(const std::string& field, double& v) {
  const char* begin = field.c_str();
  while (*begin == ' ' || *begin == '\t') ++begin;
  char* end = nullptr;
  v = std::strtod(begin, &end);
  if (end == begin) return false;
  while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
  return *end == '\0' && std::isfinite(v);
}

/// "x,y" rows; the first line may be a header; blank lines are skipped.
Points readPointsCsv(const std::string& path) {
  std::istringstream in(app::readTextFile(path));
  std::vector<double> xy;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto comma = line.find(',');
    double x = 0, y = 0;
    const bool ok = comma != std::string::npos && parseNumber(line.substr(0, comma), x) && parseNumber(line.substr(comma + 1), y);
    if (!ok) {
      if (lineNo == 1 && xy.empty()) continue;  // header
      throw app::InputError(path, "line " + std::to_string(lineNo) + ": expected two finite numbers \"x,y\", got '" + line + "'");
    }
    xy.push_back(x);
    xy.push_back(y);
  }
  if (xy.empty()) throw app::InputError(path, "no points (expected rows \"x,y\")");
  Points P(static_cast<Index>(xy.size() / 2), 2);
  for (Index i = 0; i < P.rows(); ++i) P.row(i) << xy[2 * i], xy[2 * i + 1];
  return P;
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  struct Args {
    std::string session, points, output;
  };
  auto a = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("eval", "Evaluate a session's weights at points from a CSV file");
  sub->add_option("--session", a->session, "Session file")->required();
  sub->add_option("--points", a->points, "CSV of points \"x,y\" (header optional)")->required();
  sub->add_option("-o,--output", a->output, "CSV of weights to write (header w0..w{m-1})")->required();
  sub->callback([a] {
    const app::Session s = app::loadSession(a->session);
    const Points P = readPointsCsv(a->points);
    const Weights W = s.field->weightsAt(P);
    std::string out;
    out.reserve(static_cast<std::size_t>(W.size()) * 24 + 64);
    for (Index k = 0; k < W.cols(); ++k) out += (k ? ",w" : "w") + std::to_string(k);
    out += "\n";
    char buf[32];
    for (Index i = 0; i < W.rows(); ++i) {
      for (Index k = 0; k < W.cols(); ++k) {
        std::snprintf(buf, sizeof buf, k ? ",%.17g" : "%.17g", W(i, k));
        out += buf;
      }
      out += "\n";
    }
    app::writeFileAtomic(a->output, out);
  });
}

}  // namespace kc::cli
