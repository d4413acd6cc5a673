#include "jpeg_codec.h"

#include <csetjmp>
#include <cstdio>
// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>

#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace kc::app::detail {
namespace {

// libjpeg reports errors by calling error_exit, which must not return: it longjmps to the setjmp
// in decodeInto or encodeInto. The frames it jumps over are libjpeg's; both keep every object they
// change after the setjmp behind a pointer to the caller's frame (Codec, Image, Compressed), as
// png_codec.cpp does.
struct Codec {
  jpeg_error_mgr errors{};
  std::jmp_buf jump{};
  char message[JMSG_LENGTH_MAX] = "";
  std::vector<unsigned char> cmyk;  // one row of CMYK samples (CMYK and YCCK files)
};

Codec& codecOf(j_common_ptr cinfo) { return *static_cast<Codec*>(cinfo->client_data); }

[[noreturn]] void onError(j_common_ptr cinfo) {
  Codec& d = codecOf(cinfo);
  (*cinfo->err->format_message)(cinfo, d.message);
  std::longjmp(d.jump, 1);
}
/// libjpeg's messages: a warning (level -1: corrupt or missing data, which libjpeg would paper
/// over) ends the decode like an error; trace messages (level ≥ 0) are dropped. Nothing is printed.
void onMessage(j_common_ptr cinfo, int level) {
  if (level < 0) onError(cinfo);
}
void noOutput(j_common_ptr) {}

/// Routes the errors and messages of a libjpeg (de)compressor to `d`.
template <class Info>
void reportTo(Codec& d, Info& cinfo) {
  cinfo.client_data = &d;
  cinfo.err = jpeg_std_error(&d.errors);
  d.errors.error_exit = onError;
  d.errors.emit_message = onMessage;
  d.errors.output_message = noOutput;
}

bool decodeInto(Codec& d, const std::string& bytes, int expectWidth, int expectHeight, Image& out) {
  jpeg_decompress_struct cinfo{};
  reportTo(d, cinfo);
  if (setjmp(d.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&cinfo, TRUE);
  if (int(cinfo.image_width) != expectWidth || int(cinfo.image_height) != expectHeight) {
    std::snprintf(d.message, sizeof d.message, "the frame is %ux%u, not the header's %dx%d", cinfo.image_width,
                  cinfo.image_height, expectWidth, expectHeight);
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  const bool cmyk = cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK;
  cinfo.out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
  jpeg_start_decompress(&cinfo);
  out = Image(expectWidth, expectHeight);
  d.cmyk.resize(cmyk ? std::size_t(cinfo.output_width) * 4 : 0);
  while (cinfo.output_scanline < cinfo.output_height) {
    const int y = int(cinfo.output_scanline);
    JSAMPROW row = cmyk ? d.cmyk.data() : out.pixel(0, y);
    jpeg_read_scanlines(&cinfo, &row, 1);
    if (!cmyk) continue;
    for (int x = 0; x < out.width; ++x) {  // OpenCV's icvCvt_CMYK2BGR_8u_C4C3R: c' = k − (255 − c)·k / 256
      const int c = d.cmyk[std::size_t(4 * x)], m = d.cmyk[std::size_t(4 * x + 1)], ye = d.cmyk[std::size_t(4 * x + 2)],
                k = d.cmyk[std::size_t(4 * x + 3)];
      std::uint8_t* p = out.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(k - ((255 - c) * k >> 8));
      p[1] = static_cast<std::uint8_t>(k - ((255 - m) * k >> 8));
      p[2] = static_cast<std::uint8_t>(k - ((255 - ye) * k >> 8));
      p[3] = 255;
    }
  }
  jpeg_finish_decompress(&cinfo);  // reads to the EOI marker: data missing there is a warning too
  jpeg_destroy_decompress(&cinfo);
  return true;
}

}  // namespace

bool decodeJpeg(const std::string& bytes, int expectWidth, int expectHeight, Image& out, std::string& problem) {
  Codec d;
  if (decodeInto(d, bytes, expectWidth, expectHeight, out)) return true;
  problem = d.message[0] ? d.message : "libjpeg error";
  return false;
}

namespace {

/// libjpeg's in-memory destination: the buffer it allocates (malloc) and its size.
struct Compressed {
  unsigned char* bytes = nullptr;
  unsigned long size = 0;
  ~Compressed() { std::free(bytes); }
};

/// Compresses `image` into `out`; false with d.message set on a libjpeg error. Like decodeInto,
/// what it changes after the setjmp is the caller's (Codec, Compressed).
bool encodeInto(Codec& d, const Image& image, int quality, Compressed& out) {
  jpeg_compress_struct cinfo{};
  reportTo(d, cinfo);
  if (setjmp(d.jump)) {
    jpeg_destroy_compress(&cinfo);
    return false;
  }
  jpeg_create_compress(&cinfo);
  jpeg_mem_dest(&cinfo, &out.bytes, &out.size);
  cinfo.image_width = JDIMENSION(image.width);
  cinfo.image_height = JDIMENSION(image.height);
  cinfo.input_components = 4;
  cinfo.in_color_space = JCS_EXT_RGBA;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(image.pixel(0, int(cinfo.next_scanline)));
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  return true;
}

}  // namespace

std::string encodeJpeg(const Image& image, int quality) {
  Codec d;
  Compressed out;
  if (!encodeInto(d, image, quality, out))
    throw std::runtime_error(std::string("cannot encode the JPEG image: ") + (d.message[0] ? d.message : "libjpeg error"));
  return std::string(reinterpret_cast<const char*>(out.bytes), out.size);
}

}  // namespace kc::app::detail
