#pragma once
// Test support: JPEGs that carry an Exif orientation, as phone cameras write them, TIFFs with an
// Orientation tag, as scanners write them, and a picture whose four quadrants tell how it was turned.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "kc/core/rasterize.h"

namespace kc::test {

/// A w × h picture in four solid quadrants: top-left red, top-right green, bottom-left blue,
/// bottom-right white (JPEG keeps solid blocks within a few levels away from their borders).
inline Image quadrantPicture(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool right = 2 * x >= w, bottom = 2 * y >= h;
      const Rgba c = !bottom ? (right ? Rgba{0, 255, 0, 255} : Rgba{255, 0, 0, 255})
                             : (right ? Rgba{255, 255, 255, 255} : Rgba{0, 0, 255, 255});
      std::uint8_t* p = img.pixel(x, y);
      p[0] = c.r, p[1] = c.g, p[2] = c.b, p[3] = c.a;
    }
  return img;
}

/// The quadrant colour nearest to the pixel at (x, y): 'R', 'G', 'B' or 'W'.
inline char quadrantColour(const Image& img, int x, int y) {
  const Rgba c = img.at(x, y);
  if (c.r > 128 && c.g > 128 && c.b > 128) return 'W';
  if (c.r > 128) return 'R';
  if (c.g > 128) return 'G';
  return 'B';
}

/// The colours at the centres of the four quadrants, top-left, top-right, bottom-left,
/// bottom-right: "RGBW" for quadrantPicture as stored.
inline std::string quadrantLayout(const Image& img) {
  const int x0 = img.width / 4, x1 = 3 * img.width / 4, y0 = img.height / 4, y1 = 3 * img.height / 4;
  return {quadrantColour(img, x0, y0), quadrantColour(img, x1, y0), quadrantColour(img, x0, y1), quadrantColour(img, x1, y1)};
}

/// An APP1 Exif segment (marker included) whose first directory holds `entry`, a 12-byte
/// directory entry in the byte order `bigEndian` says, or nothing when `entry` is empty.
inline std::string exifSegment(const std::string& entry, bool bigEndian) {
  std::string tiff = bigEndian ? std::string("MM\0*\0\0\0\x08", 8) : std::string("II*\0\x08\0\0\0", 8);
  const int count = entry.empty() ? 0 : 1;
  tiff += bigEndian ? std::string{'\0', char(count)} : std::string{char(count), '\0'};
  tiff += entry;
  tiff += std::string(4, '\0');  // no next directory
  const std::string body = std::string("Exif\0\0", 6) + tiff;
  const std::size_t length = body.size() + 2;
  return std::string{'\xFF', '\xE1', char(length >> 8), char(length & 0xFF)} + body;
}

/// The Orientation entry (tag 0x0112, SHORT, one value) for `value`.
inline std::string orientationEntry(int value, bool bigEndian) {
  const char v = char(value);
  return bigEndian ? std::string{'\x01', '\x12', '\0', '\x03', '\0', '\0', '\0', '\x01', '\0', v, '\0', '\0'}
                   : std::string{'\x12', '\x01', '\x03', '\0', '\x01', '\0', '\0', '\0', v, '\0', '\0', '\0'};
}

/// An uncompressed little-endian RGB TIFF of `img` (one strip) whose first directory holds the
/// Orientation `orientation` (none when 0); `tiled` adds a TileWidth entry (a header only: such a
/// file is refused before its pixels are read).
inline std::string orientedTiff(const Image& img, int orientation, bool tiled = false) {
  auto u16 = [](std::uint32_t v) { return std::string{char(v & 0xFF), char(v >> 8 & 0xFF)}; };
  auto u32 = [&](std::uint32_t v) { return u16(v & 0xFFFF) + u16(v >> 16); };
  auto entry = [&](std::uint32_t tag, std::uint32_t type, std::uint32_t count, std::uint32_t value) {
    return u16(tag) + u16(type) + u32(count) + (type == 3 && count == 1 ? u16(value) + u16(0) : u32(value));
  };
  const std::uint32_t w = std::uint32_t(img.width), h = std::uint32_t(img.height);
  const int entries = 10 + (orientation != 0) + tiled;
  const std::uint32_t bits = 8 + 2 + 12 * entries + 4, pixels = bits + 6;
  std::string ifd = entry(256, 4, 1, w) + entry(257, 4, 1, h) + entry(258, 3, 3, bits) + entry(259, 3, 1, 1) +
                    entry(262, 3, 1, 2) + entry(273, 4, 1, pixels);
  if (orientation != 0) ifd += entry(274, 3, 1, std::uint32_t(orientation));
  ifd += entry(277, 3, 1, 3) + entry(278, 4, 1, h) + entry(279, 4, 1, w * h * 3) + entry(284, 3, 1, 1);
  if (tiled) ifd += entry(322, 3, 1, 16);
  std::string out = std::string("II*\0", 4) + u32(8) + u16(std::uint32_t(entries)) + ifd + u32(0) + u16(8) + u16(8) + u16(8);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) out.append(reinterpret_cast<const char*>(img.pixel(x, y)), 3);
  return out;
}

inline void writeBytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

inline std::string slurpBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// `jpeg` (a JPEG file's bytes) with `segment` inserted right after its SOI marker.
inline std::string withSegment(const std::string& jpeg, const std::string& segment) {
  return jpeg.substr(0, 2) + segment + jpeg.substr(2);
}

}  // namespace kc::test
