#pragma once
// Test support: run the built kcwarp-cli (KC_CLI_PATH) and capture exit code, stdout and stderr;
// make scratch folders and small input files.

#include <sys/wait.h>

#include <cstdlib>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace kc::test {

struct CliResult {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

/// A fresh empty folder under the system temp dir, named after the test.
inline std::filesystem::path scratchDir(const std::string& name) {
  // The process id keeps test processes that ctest runs side by side (and other checkouts'
  // runs) out of each other's folders: one removing a folder another is writing made tests flaky.
  const auto dir = std::filesystem::temp_directory_path() / ("kcwarp_test_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Runs `kcwarp-cli <args>` (args already shell-quoted where needed) in `dir`; `cli`: another
/// build of it (a test executable with a test backend linked in).
inline CliResult runCli(const std::string& args, const std::filesystem::path& dir, const std::string& cli = KC_CLI_PATH) {
  const auto out = dir / "cli.stdout", err = dir / "cli.stderr";
  const std::string cmd =
      "cd '" + dir.string() + "' && '" + cli + "' " + args + " > '" + out.string() + "' 2> '" + err.string() + "' < /dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

/// Number of lines in s (a trailing newline does not start a new line).
/// A square cage, 64 px on a side, as a cage file.
inline constexpr const char* kSquare = R"({"version": 1, "points": [[16,16],[80,16],[80,80],[16,80]], "closed": true})";

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

inline int lineCount(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  if (!s.empty() && s.back() != '\n') ++n;
  return n;
}

}  // namespace kc::test
