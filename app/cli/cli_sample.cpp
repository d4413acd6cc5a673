// Placeholder registration until the 'sample' subcommand lands.
#include "cli_common.h"
#include "kc/app/errors.h"

namespace kc::cli {
void addSampleCommand(CLI::App& app) {
  app.add_subcommand("sample", "(not available in this build)")->callback([] {
    throw std::runtime_error("the 'sample' command is not available in this build");
  });
}
}  // namespace kc::cli
