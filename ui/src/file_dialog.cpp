#include "kc/ui/file_dialog.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

namespace kc::ui {
namespace {

namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Glob patterns of the files a dialog for `purpose` offers.
std::vector<std::string> patterns(PathPurpose purpose) {
  switch (purpose) {
    case PathPurpose::Open: return {"*.png", "*.jpg", "*.jpeg", "*.kcw.json", "*.json"};
    case PathPurpose::SaveSession: return {"*.kcw.json"};
    case PathPurpose::Export: return {"*.png"};
    case PathPurpose::LoadCage:
    case PathPurpose::SaveCage: return {"*.json"};
    case PathPurpose::None: break;
  }
  return {};
}

bool onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    std::error_code ec;
    const fs::path p = fs::path(dir.empty() ? "." : dir) / program;
    if (fs::is_regular_file(p, ec) && access(p.c_str(), X_OK) == 0) return true;
  }
  return false;
}

}  // namespace

const char* dialogTitle(PathPurpose p) {
  switch (p) {
    case PathPurpose::Open: return "Open a picture (PNG/JPEG), a session (*.kcw.json) or a cage (*.json)";
    case PathPurpose::SaveSession: return "Save session as";
    case PathPurpose::Export: return "Export the warped picture (PNG)";
    case PathPurpose::LoadCage: return "Load a cage (JSON)";
    case PathPurpose::SaveCage: return "Save the cage (JSON)";
    case PathPurpose::None: break;
  }
  return "";
}

bool isSave(PathPurpose p) { return p == PathPurpose::SaveSession || p == PathPurpose::Export || p == PathPurpose::SaveCage; }

std::string nativeDialogProgram() {
  if (const char* off = std::getenv("KCWARP_NO_NATIVE_DIALOG"); off && *off) return "";
  for (const char* program : {"zenity", "kdialog"})
    if (onPath(program)) return program;
  return "";
}

std::vector<std::string> nativeDialogCommand(const std::string& program, PathPurpose purpose, const std::string& initial) {
  std::string globs;
  for (const std::string& g : patterns(purpose)) globs += (globs.empty() ? "" : " ") + g;
  if (program == "zenity") {
    std::vector<std::string> argv = {"zenity", "--file-selection", std::string("--title=") + dialogTitle(purpose)};
    if (isSave(purpose)) {
      argv.push_back("--save");
      argv.push_back("--confirm-overwrite");
    }
    if (!initial.empty()) argv.push_back("--filename=" + initial);
    if (!globs.empty()) argv.push_back("--file-filter=" + globs);
    argv.push_back("--file-filter=All files | *");
    return argv;
  }
  if (program == "kdialog") {
    return {"kdialog", "--title", dialogTitle(purpose), isSave(purpose) ? "--getsavefilename" : "--getopenfilename",
            initial.empty() ? fs::current_path().string() : initial, globs};
  }
  return {};
}

std::optional<std::string> runForOutput(const std::vector<std::string>& argv) {
  if (argv.empty()) return std::nullopt;
  std::vector<char*> args;  // built before fork: the child only calls async-signal-safe functions
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  int fds[2];
  if (pipe(fds) != 0) return std::nullopt;
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return std::nullopt;
  }
  if (pid == 0) {
    dup2(fds[1], 1);
    close(fds[0]);
    close(fds[1]);
    execvp(args[0], args.data());
    _exit(127);
  }
  close(fds[1]);
  std::string out;
  char buffer[4096];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) > 0;) out.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
  const std::string line = out.substr(0, out.find('\n'));
  if (line.empty()) return std::nullopt;
  return line;
}

NativeDialog::NativeDialog(std::vector<std::string> argv, PathPurpose purpose, std::function<void()> wakeup)
    : m_purpose(purpose) {
  m_future = std::async(std::launch::async, [argv = std::move(argv), wakeup = std::move(wakeup)] {
    std::optional<std::string> chosen = runForOutput(argv);
    if (wakeup) wakeup();
    return chosen;
  });
}

bool NativeDialog::done() const { return m_future.wait_for(std::chrono::seconds(0)) == std::future_status::ready; }

std::optional<std::string> NativeDialog::result() { return m_future.valid() ? m_future.get() : std::nullopt; }

bool matchesPurpose(const std::string& name, PathPurpose purpose) {
  const std::string n = lower(name);
  for (const std::string& g : patterns(purpose))
    if (endsWith(n, g.substr(1))) return true;
  return false;
}

std::vector<DirEntry> listFolder(const std::string& dir, PathPurpose purpose) {
  std::vector<DirEntry> dirs, files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    std::error_code typeError;
    if (it->is_directory(typeError)) dirs.push_back({name, true});
    else if (matchesPurpose(name, purpose)) files.push_back({name, false});
  }
  auto byName = [](const DirEntry& a, const DirEntry& b) { return lower(a.name) < lower(b.name); };
  std::sort(dirs.begin(), dirs.end(), byName);
  std::sort(files.begin(), files.end(), byName);
  dirs.insert(dirs.end(), files.begin(), files.end());
  return dirs;
}

}  // namespace kc::ui
