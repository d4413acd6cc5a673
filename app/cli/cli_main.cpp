// kcwarp-cli's command line: the subcommands, parsing, exit codes (ARCHITECTURE.md, "Command line").

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "cli_common.h"
#include "cli_main.h"
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

/// Edits (insertions, deletions, substitutions, swaps of neighbours) between a and b.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

/// The name in `names` nearest to `word` when it is a likely typo of it (at most 2 edits, fewer
/// than half the word), else "".
std::string nearest(const std::string& word, const std::vector<std::string>& names) {
  std::string best;
  std::size_t bestDistance = std::min<std::size_t>(2, word.size() / 2) + 1;
  for (const std::string& n : names)
    if (const std::size_t d = editDistance(word, n); d < bestDistance) bestDistance = d, best = n;
  return best;
}

/// "did you mean" for the words CLI11 did not expect: a subcommand's name, or an option of the
/// subcommand given ("" when none is near).
std::string suggestions(const CLI::App& app, const std::vector<std::string>& words) {
  std::vector<std::string> commands, options;
  const CLI::App* chosen = nullptr;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    commands.push_back(sub->get_name());
    if (sub->parsed()) chosen = sub;
  }
  if (chosen)
    for (const CLI::Option* o : chosen->get_options())
      for (const std::string& n : o->get_lnames()) options.push_back("--" + n);
  std::string out;
  for (const std::string& w : words) {
    const std::string name = w.substr(0, w.find('='));
    const bool option = name.rfind("--", 0) == 0;
    const std::string guess = nearest(name, option ? options : chosen ? std::vector<std::string>{} : commands);
    if (!guess.empty()) out += "; '" + name + "': did you mean '" + guess + "'?";
  }
  return out;
}

/// The subcommands' names, "a, b or c".
std::string subcommandList(const CLI::App& app) {
  std::string out;
  const auto subs = app.get_subcommands([](const CLI::App*) { return true; });
  for (std::size_t k = 0; k < subs.size(); ++k) out += (k == 0 ? "" : k + 1 == subs.size() ? " or " : ", ") + subs[k]->get_name();
  return out;
}

}  // namespace

int kc::cli::runCli(int argc, char** argv) {
  guardStandardStreams();
  kc::app::preferPassiveOpenMpWaiting(argv);
  kc::app::keepMemoryReserve();
  CLI::App app{"kcwarp-cli: warp images with a cage and kernel coordinates", "kcwarp-cli"};
  app.require_subcommand(1);
  app.footer(kc::cli::limitsText());
  kc::cli::addSampleCommand(app);
  kc::cli::addBindCommand(app);
  kc::cli::addEvalCommand(app);
  kc::cli::addWarpCommand(app);
  kc::cli::addStatsCommand(app);
  kc::cli::addDemoCommand(app);
  kc::cli::addBenchCommand(app);
  for (CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    sub->footer("");  // the limits: once, in the main help
  if (argc < 2) {     // no subcommand: the list of them (one line on stderr, the help on stdout)
    std::cout << app.help();
    std::cerr << "kcwarp-cli: a subcommand is required: " << subcommandList(app) << " (kcwarp-cli SUBCOMMAND --help)\n";
    return kc::cli::kExitBadInput;
  }
  try {
    app.parse(argc, argv);
    return checkedOutput(kc::cli::kExitOk);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return checkedOutput(app.exit(e));  // --help
    // One line: CLI11's message (bounded), then a likely meant name for a mistyped subcommand or option.
    std::vector<std::string> unexpected = app.remaining();
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      if (sub->parsed())
        for (const std::string& w : sub->remaining()) unexpected.push_back(w);
    std::string text = kc::app::oneLine(e.what(), kc::app::kMaxMessageWhat);
    if (app.get_subcommands().empty() && text.find("subcommand") != std::string::npos) text += " (" + subcommandList(app) + ")";
    std::cerr << "kcwarp-cli: " << text << kc::app::oneLine(suggestions(app, unexpected), kc::app::kMaxMessageWhat) << "\n";
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
