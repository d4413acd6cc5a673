#include "cli_common.h"

#include <unistd.h>

#include "kc/app/errors.h"
#include "kc/app/image_io.h"

namespace kc::cli {

std::pair<int, int> parseSize(const std::string& text, const std::string& option) {
  const auto comma = text.find_first_of(",x");
  try {
    if (comma == std::string::npos) throw std::invalid_argument("");
    std::size_t a = 0, b = 0;
    const int w = std::stoi(text.substr(0, comma), &a);
    const int h = std::stoi(text.substr(comma + 1), &b);
    if (a != comma || b != text.size() - comma - 1 || w <= 0 || h <= 0) throw std::invalid_argument("");
    return {w, h};
  } catch (const std::exception&) {
    throw app::InputError(option, "expected a size W,H in positive whole pixels, got '" + text + "'");
  }
}

std::pair<int, int> imageSize(const std::string& path) {
  const Image img = app::loadImage(path);  // InputError naming the file when missing or unreadable
  return {img.width, img.height};
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) != 0; }

}  // namespace kc::cli
