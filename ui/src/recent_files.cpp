#include "kc/ui/recent_files.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "kc/app/file_io.h"

namespace kc::ui {

namespace fs = std::filesystem;

std::string defaultRecentFilesPath() {
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  const char* home = std::getenv("HOME");
  const fs::path base = xdg && *xdg ? fs::path(xdg) : fs::path(home ? home : "/tmp") / ".config";
  return (base / "kcwarp" / "recent.txt").string();
}

std::vector<std::string> loadRecentFiles(const std::string& listPath) {
  std::vector<std::string> recent;
  std::ifstream in(listPath);
  for (std::string line; std::getline(in, line) && recent.size() < kMaxRecentFiles;) {
    std::error_code ec;
    if (!line.empty() && fs::exists(line, ec) && std::find(recent.begin(), recent.end(), line) == recent.end())
      recent.push_back(line);
  }
  return recent;
}

void addRecentFile(std::vector<std::string>& recent, const std::string& file, const std::string& listPath) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(file, ec);
  const std::string path = ec ? file : absolute.lexically_normal().string();
  recent.erase(std::remove(recent.begin(), recent.end(), path), recent.end());
  recent.insert(recent.begin(), path);
  if (recent.size() > kMaxRecentFiles) recent.resize(kMaxRecentFiles);
  if (listPath.empty()) return;
  std::string text;
  for (const std::string& r : recent) text += r + "\n";
  try {
    fs::create_directories(fs::path(listPath).parent_path());
    app::writeFileAtomic(listPath, text);
  } catch (const std::exception&) {
    // The list is a convenience: a read-only config folder must not stop opening or saving.
  }
}

}  // namespace kc::ui
