#pragma once
/// The size of an image read from its header alone, so absurd sizes are refused before a pixel
/// is decoded (OpenCV 4.6 has no public call for this: imread decodes, then checks).

#include <cstdint>
#include <string>
#include <string_view>

namespace kc::app {

struct ImageHeader {
  std::string format;         ///< "PNG", "JPEG", "BMP", "TIFF", "WebP" or "PNM".
  std::int64_t width = 0, height = 0;  ///< As stored (the decoder's rows and columns).
  /// How the picture is meant to be shown (the Exif Orientation of a JPEG, the Orientation tag
  /// of a TIFF's first directory; 1–8): 1 as stored, 2 mirrored left-right, 3 turned 180°, 4
  /// mirrored top-bottom, 5 transposed, 6 turned 90° clockwise, 7 transversed, 8 turned 90°
  /// anticlockwise. 1 for other formats and for a missing or malformed tag.
  int orientation = 1;
  /// The size as shown: width and height swapped for orientations 5–8.
  std::int64_t uprightWidth() const { return orientation >= 5 ? height : width; }
  std::int64_t uprightHeight() const { return orientation >= 5 ? width : height; }
};

/// Formats kcwarp decodes, for messages.
inline constexpr const char* kImageFormats = "PNG, JPEG, BMP, TIFF, WebP, PNM";

/// Reads the format and the size from the first bytes of an image file (PNG IHDR, JPEG SOFn,
/// BMP info header, TIFF first IFD, WebP VP8/VP8L/VP8X, PNM P1–P6). Returns false and sets
/// `problem` (e.g. "not a PNG, JPEG, … image", "truncated PNG header") otherwise. Never reads
/// outside `bytes`.
bool readImageHeader(std::string_view bytes, ImageHeader& header, std::string& problem);

}  // namespace kc::app
