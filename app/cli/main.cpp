// kcwarp-cli: the headless face of kcwarp (ARCHITECTURE.md, "Command line").

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/process.h"

namespace {

/// A closed standard stream gets /dev/null opened read-only: no file the command opens can take
/// its number (and receive what is printed), and writing to it fails (EBADF), as checkedOutput sees.
void guardStandardStreams() {
  for (const int fd : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO})
    if (::fcntl(fd, F_GETFD) == -1 && errno == EBADF) {
      const int opened = ::open("/dev/null", O_RDONLY);
      if (opened >= 0 && opened != fd) {
        ::dup2(opened, fd);
        ::close(opened);
      }
    }
}

/// `code`, or exit 2 with one line when what the command printed could not all be written to
/// standard output (a full disk, a closed stream).
int checkedOutput(int code) {
  errno = 0;
  std::cout.flush();
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) != 0 || !std::cout.good();
  if (!failed) return code;
  std::cerr << "kcwarp-cli: standard output: cannot write what the command printed ("
            << (errno != 0 ? std::strerror(errno) : "write error") << ")\n";
  return kc::cli::kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  guardStandardStreams();
  kc::app::preferPassiveOpenMpWaiting(argv);
  kc::app::keepMemoryReserve();
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
    return checkedOutput(kc::cli::kExitOk);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return checkedOutput(app.exit(e));  // --help
    // One line however long or multi-line the argument it quotes (InputError's messages already are).
    std::cerr << "kcwarp-cli: " << kc::app::oneLine(e.what(), kc::app::kMaxMessageWhat) << "\n";
    return kc::cli::kExitBadInput;
  } catch (const kc::app::InputError& e) {
    std::cerr << "kcwarp-cli: " << e.what() << "\n";
    return kc::cli::kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "kcwarp-cli: out of memory: this input needs more memory than the machine has; use a larger --spacing, "
                 "a smaller image or a cage with fewer points\n";
    return kc::cli::kExitBadInput;
  } catch (const std::exception& e) {  // std::invalid_argument included: misuse of an internal API
    std::cerr << "kcwarp-cli: internal error: " << kc::app::oneLine(e.what(), kc::app::kMaxMessageWhat) << "\n";
    return kc::cli::kExitInternal;
  }
}
