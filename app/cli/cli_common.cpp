#include "cli_common.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "kc/app/errors.h"
#include "kc/app/image_io.h"
#include "kc/app/limits.h"

namespace kc::cli {

std::pair<int, int> parseSize(const std::string& text, const std::string& option) {
  const auto comma = text.find_first_of(",x");
  try {
    if (comma == std::string::npos) throw std::invalid_argument("");
    std::size_t a = 0, b = 0;
    const int w = std::stoi(text.substr(0, comma), &a);
    const int h = std::stoi(text.substr(comma + 1), &b);
    if (a != comma || b != text.size() - comma - 1 || w <= 0 || h <= 0) throw std::invalid_argument("");
    app::checkImageSize(w, h, option, "image");
    return {w, h};
  } catch (const app::InputError&) {
    throw;
  } catch (const std::exception&) {
    throw app::InputError(option, "expected a size W,H in positive whole pixels, got '" + text + "'");
  }
}

std::pair<int, int> imageSize(const std::string& path) {
  const Image img = app::loadImage(path);  // InputError naming the file when missing or unreadable
  return {img.width, img.height};
}

std::pair<int, int> imageHeaderSize(const std::string& path) {
  const app::ImageHeader header = app::readImageFileHeader(path);  // InputError naming the file
  return {static_cast<int>(header.uprightWidth()), static_cast<int>(header.uprightHeight())};  // as loadImage lays it out
}

void requireFinite(double value, const std::string& option, const std::string& unit) {
  if (!std::isfinite(value)) throw app::InputError(option, unit.empty() ? "must be a finite number" : "must be a finite number of " + unit);
}

void addPngCompressionOption(CLI::App* sub, int& level) {
  level = app::kDefaultPngCompression;
  sub->add_option("--png-compression", level,
                  "zlib level of the PNGs written: 0 stores, 1 fastest, 9 smallest (a 12-megapixel picture: "
                  "about 1-2 s at 1, 6-40 s at 9)")
      ->check(CLI::Range(0, 9))
      ->capture_default_str();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

std::string limitsText() {
  using namespace app;
  auto n = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return std::string(buf);
  };
  return "Limits (beyond them the input is refused with exit 2 before any work):\n"
         "  files: cage/pose " + byteText(double(kMaxJsonFileBytes)) + ", session " + byteText(double(kMaxSessionFileBytes)) +
         ", points CSV " + byteText(double(kMaxPointsFileBytes)) + ", image " + byteText(double(kMaxImageFileBytes)) +
         "; regular files only\n"
         "  images: side <= " + std::to_string(kMaxImageSide) + " px, <= " + n(double(kMaxImagePixels)) +
         " pixels (64 megapixels), checked from the header\n"
         "  cage: <= " + std::to_string(kMaxCagePoints) + " points; coordinates |x| <= 1e7 px; session weights |w| <= 1e6\n"
         "  bind: <= " + n(double(kMaxBindSamples)) + " samples, <= " + n(double(kMaxKernelNonZeros)) +
         " kernel non-zeros, <= " + byteText(kMaxBindBytes) + " estimated memory; --spacing >= " + n(kMinSpacing * 100) +
         "/100 px; --heat-iterations <= " + std::to_string(kMaxHeatIterations) + "\n"
         "  eval: <= " + n(double(kMaxEvalWeights)) + " weights (points x control points); a JSON file parsed: <= " +
         byteText(kMaxJsonParseBytes) + " estimated memory\n"
         "Outputs are written atomically (a temporary file in the target's folder, then renamed); a symbolic link is\n"
         "written through to its target; devices, FIFOs and folders are refused; a failing command writes nothing.";
}

CLI::Validator seedCheck() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::uint64_t v = 0;
        const char* end = text.data() + text.size();
        const auto [stop, ec] = std::from_chars(text.data(), end, v);
        if (text.empty() || ec != std::errc() || stop != end)
          return "must be a whole number from 0 to 18446744073709551615, got '" + text + "'";
        return "";
      },
      "0..2^64-1");
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) != 0; }

}  // namespace kc::cli
