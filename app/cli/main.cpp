// kcwarp-cli: the headless face of kcwarp (ARCHITECTURE.md, "Command line").

#include <iostream>
#include <new>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/process.h"

int main(int argc, char** argv) {
  kc::app::preferPassiveOpenMpWaiting(argv);
  CLI::App app{"kcwarp-cli: warp images with a cage and kernel coordinates"};
  app.require_subcommand(1);
  app.footer(kc::cli::limitsText());
  kc::cli::addSampleCommand(app);
  kc::cli::addBindCommand(app);
  kc::cli::addEvalCommand(app);
  kc::cli::addWarpCommand(app);
  kc::cli::addStatsCommand(app);
  kc::cli::addDemoCommand(app);
  kc::cli::addBenchCommand(app);
  try {
    app.parse(argc, argv);
    return kc::cli::kExitOk;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::cerr << "kcwarp-cli: " << e.what() << "\n";
    return kc::cli::kExitBadInput;
  } catch (const kc::app::InputError& e) {
    std::cerr << "kcwarp-cli: " << e.what() << "\n";
    return kc::cli::kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "kcwarp-cli: out of memory: this input needs more memory than the machine has; use a larger --spacing, "
                 "a smaller image or a cage with fewer points\n";
    return kc::cli::kExitBadInput;
  } catch (const std::exception& e) {  // std::invalid_argument included: misuse of an internal API
    std::cerr << "kcwarp-cli: internal error: " << e.what() << "\n";
    return kc::cli::kExitInternal;
  }
}
