#pragma once
/// The size of an image read from its header alone, so absurd sizes are refused before a pixel
/// is decoded (OpenCV 4.6 has no public call for this: imread decodes, then checks).

#include <cstdint>
#include <string>
#include <string_view>

namespace kc::app {

struct ImageHeader {
  std::string format;         ///< "PNG", "JPEG", "BMP", "TIFF", "WebP" or "PNM".
  std::int64_t width = 0, height = 0;
};

/// Formats kcwarp decodes, for messages.
inline constexpr const char* kImageFormats = "PNG, JPEG, BMP, TIFF, WebP, PNM";

/// Reads the format and the size from the first bytes of an image file (PNG IHDR, JPEG SOFn,
/// BMP info header, TIFF first IFD, WebP VP8/VP8L/VP8X, PNM P1–P6). Returns false and sets
/// `problem` (e.g. "not a PNG, JPEG, … image", "truncated PNG header") otherwise. Never reads
/// outside `bytes`.
bool readImageHeader(std::string_view bytes, ImageHeader& header, std::string& problem);

}  // namespace kc::app
