#include "kc/app/image_header.h"

#include <algorithm>
#include <cctype>
#include <cstdint>

namespace kc::app {
namespace {

/// Bounds-checked little/big-endian reads over the header bytes.
struct Reader {
  std::string_view b;
  bool has(std::size_t at, std::size_t n) const { return at <= b.size() && n <= b.size() - at; }
  std::uint32_t u8(std::size_t at) const { return static_cast<unsigned char>(b[at]); }
  std::uint32_t be16(std::size_t at) const { return u8(at) << 8 | u8(at + 1); }
  std::uint32_t le16(std::size_t at) const { return u8(at) | u8(at + 1) << 8; }
  std::uint32_t be32(std::size_t at) const { return be16(at) << 16 | be16(at + 2); }
  std::uint32_t le32(std::size_t at) const { return le16(at) | le16(at + 2) << 16; }
  std::uint32_t le24(std::size_t at) const { return le16(at) | u8(at + 2) << 16; }
};

bool fail(std::string& problem, const char* text) {
  problem = text;
  return false;
}

bool png(const Reader& r, ImageHeader& h, std::string& problem) {
  // Signature (8), IHDR length (4), "IHDR", width, height (big-endian).
  if (!r.has(0, 24) || r.b.substr(12, 4) != "IHDR") return fail(problem, "truncated or malformed PNG header");
  h.width = r.be32(16);
  h.height = r.be32(20);
  return true;
}

/// The Orientation (tag 0x0112) of the first directory of the TIFF structure in bytes [begin, end)
/// of r (an Exif block), or 1 when there is none or the structure is malformed: a picture is not
/// refused for its metadata.
int tiffOrientation(const Reader& r, std::size_t begin, std::size_t end) {
  if (end > r.b.size() || begin > end || end - begin < 8) return 1;
  const bool little = r.b[begin] == 'I' && r.b[begin + 1] == 'I';
  if (!little && !(r.b[begin] == 'M' && r.b[begin + 1] == 'M')) return 1;
  auto u16 = [&](std::size_t at) { return little ? r.le16(at) : r.be16(at); };
  auto u32 = [&](std::size_t at) { return little ? r.le32(at) : r.be32(at); };
  if (u16(begin + 2) != 42) return 1;
  const std::size_t ifd = u32(begin + 4);
  if (ifd > end - begin - 2) return 1;
  const std::size_t first = begin + ifd, count = u16(first);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t e = first + 2 + 12 * k;
    if (e + 12 > end) return 1;
    if (u16(e) != 0x0112) continue;
    const std::uint32_t value = u16(e + 2) == 3 ? u16(e + 8) : 0;  // SHORT, one value
    return value >= 1 && value <= 8 ? int(value) : 1;
  }
  return 1;
}

bool jpeg(const Reader& r, ImageHeader& h, std::string& problem) {
  std::size_t at = 2;
  while (r.has(at, 2)) {
    if (r.u8(at) != 0xFF) return fail(problem, "malformed JPEG: expected a marker");
    const std::uint32_t marker = r.u8(at + 1);
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    at += 2;
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue;  // markers without a segment
    if (marker == 0xD9 || marker == 0xDA) break;                          // end of image, start of scan
    if (!r.has(at, 2)) break;
    const std::uint32_t length = r.be16(at);
    if (length < 2) return fail(problem, "malformed JPEG: bad segment length");
    // APP1 "Exif\0\0": a TIFF structure whose Orientation says how the picture is shown.
    if (marker == 0xE1 && h.orientation == 1 && r.has(at + 2, 6) && r.b.substr(at + 2, 6) == std::string_view("Exif\0\0", 6))
      h.orientation = tiffOrientation(r, at + 8, std::min(r.b.size(), at + length));
    const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame) {
      if (!r.has(at, 7)) break;
      h.height = r.be16(at + 3);
      h.width = r.be16(at + 5);
      if (h.height == 0) return fail(problem, "JPEG without its height in the frame header (DNL) is not supported");
      return true;
    }
    at += length;
  }
  return fail(problem, "truncated or malformed JPEG: no frame header");
}

bool bmp(const Reader& r, ImageHeader& h, std::string& problem) {
  if (!r.has(14, 4)) return fail(problem, "truncated BMP header");
  const std::uint32_t info = r.le32(14);
  if (info == 12) {
    if (!r.has(18, 4)) return fail(problem, "truncated BMP header");
    h.width = r.le16(18);
    h.height = r.le16(20);
    return true;
  }
  // The DIB header sizes of BITMAPINFOHEADER (40) and its successors (52, 56, 64 for OS/2 2.x, 108, 124).
  if ((info != 40 && info != 52 && info != 56 && info != 64 && info != 108 && info != 124) || !r.has(18, 8))
    return fail(problem, "truncated or malformed BMP header");
  h.width = static_cast<std::int32_t>(r.le32(18));
  const std::int64_t height = static_cast<std::int32_t>(r.le32(22));
  h.height = height < 0 ? -height : height;  // negative: rows stored top-down
  return true;
}

bool tiff(const Reader& r, ImageHeader& h, std::string& problem) {
  const bool little = r.b[0] == 'I';
  auto u16 = [&](std::size_t at) { return little ? r.le16(at) : r.be16(at); };
  auto u32 = [&](std::size_t at) { return little ? r.le32(at) : r.be32(at); };
  if (!r.has(0, 8)) return fail(problem, "truncated TIFF header");
  if (u16(2) != 42) return fail(problem, "BigTIFF and other TIFF variants are not supported");
  const std::size_t ifd = u32(4);
  if (!r.has(ifd, 2)) return fail(problem, "truncated TIFF: the first directory lies past the end of the file");
  const std::uint32_t count = u16(ifd);
  bool haveW = false, haveH = false, tiled = false;
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::size_t e = ifd + 2 + 12 * static_cast<std::size_t>(k);
    if (!r.has(e, 12)) return fail(problem, "truncated TIFF directory");
    const std::uint32_t tag = u16(e), type = u16(e + 2);
    tiled = tiled || tag == 322;  // TileWidth
    if (tag != 256 && tag != 257) continue;
    std::int64_t v = 0;
    if (type == 3) v = u16(e + 8);        // SHORT
    else if (type == 4) v = u32(e + 8);   // LONG
    else return fail(problem, "malformed TIFF: image size of an unexpected type");
    (tag == 256 ? h.width : h.height) = v;
    (tag == 256 ? haveW : haveH) = true;
  }
  if (!haveW || !haveH) return fail(problem, "malformed TIFF: no image width or length");
  // Scanners and cameras say how to show the picture as JPEG's Exif does (the same tag). OpenCV's
  // TIFF decoder turns the picture by it, and scrambles a tiled one.
  h.orientation = tiffOrientation(r, 0, r.b.size());
  if (tiled && h.orientation != 1)
    return fail(problem, "a tiled TIFF turned by its Orientation tag is not supported: save it in strips, or upright");
  return true;
}

bool webp(const Reader& r, ImageHeader& h, std::string& problem) {
  if (!r.has(12, 18)) return fail(problem, "truncated WebP header");
  const std::string_view chunk = r.b.substr(12, 4);
  if (chunk == "VP8X") {
    h.width = std::int64_t(r.le24(24)) + 1;
    h.height = std::int64_t(r.le24(27)) + 1;
    return true;
  }
  if (chunk == "VP8L") {
    if (r.u8(20) != 0x2F) return fail(problem, "malformed WebP (lossless) header");
    const std::uint32_t bits = r.le32(21);
    h.width = std::int64_t(bits & 0x3FFF) + 1;
    h.height = std::int64_t((bits >> 14) & 0x3FFF) + 1;
    return true;
  }
  if (chunk == "VP8 ") {
    if (r.u8(23) != 0x9D || r.u8(24) != 0x01 || r.u8(25) != 0x2A) return fail(problem, "malformed WebP (lossy) header");
    h.width = r.le16(26) & 0x3FFF;
    h.height = r.le16(28) & 0x3FFF;
    return true;
  }
  return fail(problem, "unsupported WebP variant");
}

bool pnm(const Reader& r, ImageHeader& h, std::string& problem) {
  std::size_t at = 2;
  std::int64_t v[2] = {0, 0};
  for (std::int64_t& x : v) {
    for (;;) {  // whitespace and comments
      while (at < r.b.size() && std::isspace(static_cast<unsigned char>(r.b[at]))) ++at;
      if (at < r.b.size() && r.b[at] == '#') {
        while (at < r.b.size() && r.b[at] != '\n') ++at;
        continue;
      }
      break;
    }
    std::size_t digits = 0;
    while (at < r.b.size() && std::isdigit(static_cast<unsigned char>(r.b[at])) && digits < 12) {
      x = 10 * x + (r.b[at++] - '0');
      ++digits;
    }
    if (digits == 0 || digits == 12) return fail(problem, "truncated or malformed PNM header");
  }
  h.width = v[0];
  h.height = v[1];
  return true;
}

}  // namespace

bool readImageHeader(std::string_view bytes, ImageHeader& header, std::string& problem) {
  const Reader r{bytes};
  header = ImageHeader{};
  if (bytes.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) return header.format = "PNG", png(r, header, problem);
  if (r.has(0, 3) && r.u8(0) == 0xFF && r.u8(1) == 0xD8 && r.u8(2) == 0xFF) return header.format = "JPEG", jpeg(r, header, problem);
  if (bytes.substr(0, 2) == "BM") return header.format = "BMP", bmp(r, header, problem);
  if (bytes.substr(0, 4) == std::string_view("II*\0", 4) || bytes.substr(0, 4) == std::string_view("MM\0*", 4) ||
      bytes.substr(0, 4) == std::string_view("II+\0", 4) || bytes.substr(0, 4) == std::string_view("MM\0+", 4))
    return header.format = "TIFF", tiff(r, header, problem);
  if (r.has(0, 12) && bytes.substr(0, 4) == "RIFF" && bytes.substr(8, 4) == "WEBP") return header.format = "WebP", webp(r, header, problem);
  if (r.has(0, 2) && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '6') return header.format = "PNM", pnm(r, header, problem);
  problem = std::string("not an image kcwarp reads (") + kImageFormats + ")";
  return false;
}

}  // namespace kc::app
