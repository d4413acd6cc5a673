#include "png_codec.h"

#include <png.h>
#include <zlib.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace kc::app::detail {
namespace {

// libpng reports errors by longjmp to the setjmp in the function that called it. The frames it
// jumps over are libpng's and the callbacks below, none of which own C++ objects; the functions
// holding the setjmp keep every object they change after it behind a pointer to the caller's
// frame (Io, Image), so nothing with a destructor is left half-updated in a jumped-to frame.
struct Io {
  const unsigned char* data = nullptr;  // decoding: the file content
  std::size_t size = 0;
  std::size_t pos = 0;
  std::string* out = nullptr;           // encoding: the file being written
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
void writeBytes(png_structp png, png_bytep src, std::size_t n) {
  static_cast<Io*>(png_get_io_ptr(png))->out->append(reinterpret_cast<const char*>(src), n);
}
void flushBytes(png_structp) {}

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

/// Encodes `image` into *io.out; false after a libpng error (io.message).
bool encodeFrom(Io& io, const Image& image, int level) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &io, onError, onWarning);
  if (!png) return std::snprintf(io.message, sizeof io.message, "out of memory"), false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return std::snprintf(io.message, sizeof io.message, "out of memory"), false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &io, writeBytes, flushBytes);
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGBA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, level);
  // Every row filtered with Up instead of libpng's per-row choice among five (which filters each
  // row five ways). Level 1 on 12 MP, one run: photo 1.14 s / 7.7 MB against 2.75 s / 8.6 MB,
  // noisy 2.0 s / 10.4 MB against 4.0 s / 10.1 MB, flat illustration 0.36 s against 1.13 s (same
  // size); the sample plot of `kcwarp-cli sample` is smaller too. One filter for every level keeps
  // a higher level from giving a larger file.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  // zlib's default strategy: libpng picks Z_FILTERED for filtered rows, which at levels 4..9 drops
  // the short matches that drawings and plots are made of (the sample plot of `kcwarp-cli sample`
  // came out 28% larger at level 9 than at level 1).
  png_set_compression_strategy(png, Z_DEFAULT_STRATEGY);
  png_write_info(png, info);
  png_write_image(png, io.rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

bool decodePng(const std::string& bytes, Image& out, std::string& problem) {
  Io io;
  io.data = reinterpret_cast<const unsigned char*>(bytes.data());
  io.size = bytes.size();
  if (decodeInto(io, out)) return true;
  problem = io.message;
  return false;
}

std::string encodePng(const Image& image, int level) {
  std::string file;
  Io io;
  io.out = &file;
  file.reserve(image.rgba.size() / 2 + 1024);
  io.rows.resize(std::size_t(image.height));
  for (int y = 0; y < image.height; ++y) io.rows[std::size_t(y)] = const_cast<png_bytep>(image.pixel(0, y));
  if (!encodeFrom(io, image, level)) throw std::runtime_error(std::string("libpng could not encode the image: ") + io.message);
  return file;
}

}  // namespace kc::app::detail
