#include "png_codec.h"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include "kc/app/limits.h"
#include "kc/core/parallel.h"

namespace kc::app::detail {
namespace {

/// Largest PNG chunk other than IDAT (text, ICC profile, unknown chunks) read into memory, bytes.
constexpr png_alloc_size_t kMaxPngChunkBytes = 8 * kMiB;
/// Most ancillary chunks (text, sPLT, unknown) kept while reading one file.
constexpr png_uint_32 kMaxPngCachedChunks = 1000;

// libpng reports errors by longjmp to the setjmp in the function that called it. The frames it
// jumps over are libpng's and the callbacks below, none of which own C++ objects; the functions
// holding the setjmp keep every object they change after it behind a pointer to the caller's
// frame (Io, Image), so nothing with a destructor is left half-updated in a jumped-to frame.
struct Io {
  const unsigned char* data = nullptr;  // decoding: the file content
  std::size_t size = 0;
  std::size_t pos = 0;
  std::vector<png_bytep> rows;
  char message[256] = "";
};

void onError(png_structp png, png_const_charp msg) {
  auto* io = static_cast<Io*>(png_get_error_ptr(png));
  std::snprintf(io->message, sizeof io->message, "%s", msg ? msg : "libpng error");
  png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}  // ancillary-chunk trouble: the pixels still decode

void readBytes(png_structp png, png_bytep dst, std::size_t n) {
  auto* io = static_cast<Io*>(png_get_io_ptr(png));
  if (n > io->size - io->pos) png_error(png, "the file is truncated");
  std::memcpy(dst, io->data + io->pos, n);
  io->pos += n;
}

/// The chunks' length fields, read before libpng sees the file: libpng allocates a text chunk's
/// claimed length before reading it (2 GiB for a 56-byte file claiming 0x7ffffff0 bytes), whatever
/// png_set_chunk_malloc_max says. False with `problem` set for a chunk longer than what is left of
/// the file (truncated) or, other than IDAT, longer than kMaxPngChunkBytes.
bool checkChunkLengths(const std::string& bytes, std::string& problem) {
  auto be32 = [&](std::size_t at) {
    return std::uint32_t(std::uint8_t(bytes[at])) << 24 | std::uint32_t(std::uint8_t(bytes[at + 1])) << 16 |
           std::uint32_t(std::uint8_t(bytes[at + 2])) << 8 | std::uint32_t(std::uint8_t(bytes[at + 3]));
  };
  for (std::size_t at = 8; at + 8 <= bytes.size();) {  // after the signature: length, type, data, CRC
    const std::uint64_t length = be32(at);
    const std::string type = bytes.substr(at + 4, 4);
    char text[160];
    if (type != "IDAT" && length > kMaxPngChunkBytes) {
      std::snprintf(text, sizeof text, "a chunk claims %llu bytes, more than the %llu kcwarp reads for one chunk",
                    static_cast<unsigned long long>(length), static_cast<unsigned long long>(kMaxPngChunkBytes));
      return problem = text, false;
    }
    if (length + 12 > bytes.size() - at) return problem = "the file is truncated", false;
    if (type == "IEND") break;
    at += std::size_t(length) + 12;
  }
  return true;
}

/// Decodes into `out` with the transforms of decodePng; false after a libpng error (io.message).
bool decodeInto(Io& io, Image& out) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &io, onError, onWarning);
  if (!png) return std::snprintf(io.message, sizeof io.message, "out of memory"), false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return std::snprintf(io.message, sizeof io.message, "out of memory"), false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, &io, readBytes);
  // Bounded before anything is allocated: a chunk other than IDAT longer than kMaxPngChunkBytes is
  // refused from its length field ("chunk data is too large"), as is a side beyond kcwarp's.
  png_set_chunk_malloc_max(png, kMaxPngChunkBytes);
  png_set_chunk_cache_max(png, kMaxPngCachedChunks);
  png_set_user_limits(png, kMaxImageSide, kMaxImageSide);
  png_read_info(png, info);
  const int colour = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  const bool transparency = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
  if (colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colour == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (transparency) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_scale_16(png);
  if (colour == PNG_COLOR_TYPE_GRAY || colour == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  if (!(colour & PNG_COLOR_MASK_ALPHA) && !transparency) png_set_filler(png, 0xFF, PNG_FILLER_AFTER);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  if (png_get_rowbytes(png, info) != std::size_t(w) * 4) png_error(png, "unexpected row layout after conversion");
  // The caller checked the header's size against kcwarp's limits before calling.
  out = Image(int(w), int(h));
  io.rows.resize(h);
  for (png_uint_32 y = 0; y < h; ++y) io.rows[y] = out.pixel(0, int(y));
  png_read_image(png, io.rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

constexpr std::size_t kStripBytes = std::size_t(1) << 19;  // filtered bytes per compressed strip
constexpr std::size_t kWindowBytes = 32768;                 // deflate's window: a strip's priming

/// Rows per strip for rows of `rowBytes` filtered bytes (filter byte included), at least one.
int stripRows(std::size_t rowBytes) { return int(std::max<std::size_t>(1, kStripBytes / rowBytes)); }

/// Rows [y0, y1) of `image` (RGBA, as written) as PNG filtered rows at `out`: the filter byte, Up
/// (2) or None (0) for the image's first row, then each byte minus the one above it.
/// Up for every row instead of libpng's per-row choice among five (which filters each row five
/// ways): measured with libpng at level 1 on 12 MP, photo 1.14 s / 7.7 MB against 2.75 s / 8.6 MB,
/// noisy 2.0 s / 10.4 MB against 4.0 s / 10.1 MB, flat illustration 0.36 s against 1.13 s (same
/// size). One filter for every level keeps a higher level from giving a larger file.
void filterRows(const Image& image, int y0, int y1, unsigned char* out) {
  const std::size_t bytes = 4 * std::size_t(image.width);
  for (int y = y0; y < y1; ++y) {
    const std::uint8_t* row = image.pixel(0, y);
    const std::uint8_t* up = y > 0 ? image.pixel(0, y - 1) : nullptr;
    *out++ = up ? 2 : 0;
    if (!up) std::memcpy(out, row, bytes);
    else
      for (std::size_t b = 0; b < bytes; ++b) out[b] = std::uint8_t(row[b] - up[b]);
    out += bytes;
  }
}

/// One strip's part of the IDAT stream.
struct Piece {
  std::unique_ptr<unsigned char[]> deflated;  // raw deflate data ending with a full flush (the last strip: Z_FINISH)
  std::size_t size = 0;                       // bytes in `deflated`
  uLong crc = 0;                              // CRC-32 of `deflated`
  uLong adler = 1;                            // Adler-32 of the strip's filtered rows
  std::size_t filteredBytes = 0;
};

/// A raw-deflate compressor (no zlib header or trailer: the pieces share the file's) that ends
/// itself. zlib's default strategy: Z_FILTERED (libpng's pick for filtered rows) drops, at levels
/// 4..9, the short matches that drawings and plots are made of (the sample plot of `kcwarp-cli
/// sample` came out 28% larger at level 9 than at level 1).
struct Deflater {
  z_stream zs{};
  explicit Deflater(int level) {
    if (deflateInit2(&zs, level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
      throw std::runtime_error("zlib could not start compressing (out of memory)");
  }
  ~Deflater() { deflateEnd(&zs); }
  Deflater(const Deflater&) = delete;
  Deflater& operator=(const Deflater&) = delete;
};

/// Filters rows [y0, y1) and deflates them as one piece, its window primed with the filtered rows
/// of up to 32 KB before y0 (which the decoder has just produced when it reaches this piece).
void compressStrip(const Image& image, int level, int y0, int y1, bool last, Piece& piece) {
  const std::size_t rowBytes = 1 + 4 * std::size_t(image.width);
  const int primeRows = std::min(y0, int((kWindowBytes + rowBytes - 1) / rowBytes));
  const std::size_t primed = std::size_t(primeRows) * rowBytes, n = std::size_t(y1 - y0) * rowBytes;
  const auto filtered = std::make_unique_for_overwrite<unsigned char[]>(primed + n);
  filterRows(image, y0 - primeRows, y1, filtered.get());
  const unsigned char* input = filtered.get() + primed;
  piece.filteredBytes = n;
  piece.adler = adler32(1, input, uInt(n));

  Deflater d(level);
  if (primed > 0) {
    const std::size_t window = std::min(primed, kWindowBytes);
    if (deflateSetDictionary(&d.zs, input - window, uInt(window)) != Z_OK)
      throw std::runtime_error("zlib could not prime a strip's window");
  }
  std::size_t capacity = deflateBound(&d.zs, uLong(n)) + 64;  // + the flush's empty stored block
  piece.deflated = std::make_unique_for_overwrite<unsigned char[]>(capacity);
  d.zs.next_in = const_cast<unsigned char*>(input);
  d.zs.avail_in = uInt(n);
  for (;;) {
    d.zs.next_out = piece.deflated.get() + piece.size;
    d.zs.avail_out = uInt(capacity - piece.size);
    const int status = deflate(&d.zs, last ? Z_FINISH : Z_FULL_FLUSH);
    piece.size = capacity - d.zs.avail_out;
    if (status == Z_STREAM_ERROR) throw std::runtime_error("zlib could not compress a strip");
    if (last ? status == Z_STREAM_END : d.zs.avail_in == 0 && d.zs.avail_out != 0) break;
    auto larger = std::make_unique_for_overwrite<unsigned char[]>(2 * capacity);  // never expected
    std::memcpy(larger.get(), piece.deflated.get(), piece.size);
    piece.deflated = std::move(larger);
    capacity *= 2;
  }
  piece.crc = crc32(0, piece.deflated.get(), uInt(piece.size));
}

void putBe32(std::string& file, std::uint32_t v) {
  const char b[4] = {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  file.append(b, 4);
}

/// Appends a chunk: length, type, `head`, the `body` bytes whose CRC-32 is `bodyCrc`, `tail`, and
/// the CRC-32 of all but the length.
void appendChunk(std::string& file, const char* type, const std::string& head, const unsigned char* body,
                 std::size_t bodySize, uLong bodyCrc, const std::string& tail) {
  putBe32(file, std::uint32_t(head.size() + bodySize + tail.size()));
  const std::size_t start = file.size();
  file.append(type, 4);
  file += head;
  uLong crc = crc32(0, reinterpret_cast<const Bytef*>(file.data() + start), uInt(file.size() - start));
  file.append(reinterpret_cast<const char*>(body), bodySize);
  crc = crc32_combine(crc, bodyCrc, z_off_t(bodySize));
  file += tail;
  crc = crc32(crc, reinterpret_cast<const Bytef*>(tail.data()), uInt(tail.size()));
  putBe32(file, std::uint32_t(crc));
}

/// The 2-byte zlib header of a deflate stream with a 32 KB window at `level` (RFC 1950).
std::string zlibHeader(int level) {
  const unsigned flevel = level < 2 ? 0 : level < 6 ? 1 : level == 6 ? 2 : 3;
  unsigned header = (0x78u << 8) | (flevel << 6);
  header += 31 - header % 31;
  return {char(header >> 8), char(header & 0xFF)};
}

}  // namespace

bool decodePng(const std::string& bytes, Image& out, std::string& problem) {
  if (!checkChunkLengths(bytes, problem)) return false;
  Io io;
  io.data = reinterpret_cast<const unsigned char*>(bytes.data());
  io.size = bytes.size();
  if (decodeInto(io, out)) return true;
  problem = io.message;
  return false;
}

std::string encodePng(const Image& image, int level) {
  const int rows = stripRows(1 + 4 * std::size_t(image.width));
  const int strips = (image.height + rows - 1) / rows;
  std::vector<Piece> pieces(static_cast<std::size_t>(strips));
  parallelFor(strips, [&](Index k) {
    const int y0 = int(k) * rows;
    compressStrip(image, level, y0, std::min(image.height, y0 + rows), k + 1 == strips,
                            pieces[std::size_t(k)]);
  }, 1);
  uLong adler = pieces[0].adler;
  std::size_t total = 8 + 25 + 12 + 6;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (k > 0) adler = adler32_combine(adler, pieces[k].adler, z_off_t(pieces[k].filteredBytes));
    total += 12 + pieces[k].size;
  }
  std::string file;
  file.reserve(total);
  file.append("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  putBe32(ihdr, std::uint32_t(image.width));
  putBe32(ihdr, std::uint32_t(image.height));
  // Always RGBA: ARCHITECTURE.md's contract for what `warp` writes. 8 bit, RGBA, deflate, adaptive
  // filters, not interlaced.
  ihdr += {char(8), char(6), 0, 0, 0};
  appendChunk(file, "IHDR", ihdr, nullptr, 0, 0, "");
  std::string trailer;
  putBe32(trailer, std::uint32_t(adler));
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    appendChunk(file, "IDAT", k == 0 ? zlibHeader(level) : "", pieces[k].deflated.get(), pieces[k].size, pieces[k].crc,
                k + 1 == pieces.size() ? trailer : "");
    pieces[k].deflated.reset();  // the file grows as the pieces go
  }
  appendChunk(file, "IEND", "", nullptr, 0, 0, "");
  return file;
}

}  // namespace kc::app::detail
