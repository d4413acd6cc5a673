#pragma once
/// Recently opened and saved files (File > Open recent), kept in a plain text file, one path a
/// line, newest first.

#include <string>
#include <vector>

namespace kc::ui {

/// Most entries kept.
inline constexpr std::size_t kMaxRecentFiles = 10;

/// Default list file: $XDG_CONFIG_HOME or ~/.config, then kcwarp/recent.txt.
std::string defaultRecentFilesPath();

/// Reads the list (missing file: empty list; lines of files that no longer exist are dropped).
std::vector<std::string> loadRecentFiles(const std::string& listPath);

/// Puts `file` (made absolute) first in `recent`, removing an older copy and trimming to
/// kMaxRecentFiles; writes the list to `listPath` atomically when it is not empty.
void addRecentFile(std::vector<std::string>& recent, const std::string& file, const std::string& listPath);

}  // namespace kc::ui
