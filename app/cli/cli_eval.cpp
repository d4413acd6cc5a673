// kcwarp-cli eval: weights of a session at arbitrary points.

#include <cstdio>
#include <memory>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/limits.h"
#include "kc/app/points_csv.h"

namespace kc::cli {

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
    app::checkOutputFile(a->output);
    const app::Session s = app::loadSession(a->session);
    const Points P = app::loadPointsCsv(a->points);
    const long long weights = static_cast<long long>(P.rows()) * static_cast<long long>(s.cage.size());
    if (weights > app::kMaxEvalWeights)
      throw app::InputError(a->points, std::to_string(P.rows()) + " points x " + std::to_string(s.cage.size()) +
                                           " control points are " + std::to_string(weights) + " weights, above kcwarp's limit of " +
                                           std::to_string(app::kMaxEvalWeights) + " for one eval (about 2 GB); split the file into parts of at most " +
                                           std::to_string(app::kMaxEvalWeights / s.cage.size()) + " points");
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
