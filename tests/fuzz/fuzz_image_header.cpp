// libFuzzer target: the image header check (PNG, JPEG, BMP, TIFF, WebP, PNM) and the size limits,
// then, for a PNG or a JPEG that passes them, kcwarp's own decoder (app/src/png_codec.cpp: libpng,
// app/src/jpeg_codec.cpp: libjpeg, both with setjmp error handling) — up to a million pixels, so a
// run stays fast.
#include "fuzz_support.h"
#include "jpeg_codec.h"
#include "kc/app/image_header.h"
#include "kc/app/limits.h"
#include "png_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return kc::fuzz::runLoader(data, size, [](const std::string& text) {
    kc::app::ImageHeader header;
    std::string problem;
    if (!kc::app::readImageHeader(text, header, problem)) {
      if (problem.empty()) __builtin_trap();  // a refusal always says why
      return;
    }
    kc::app::checkImageSize(header.width, header.height, "fuzz.image", header.format + " image");
    if ((header.format != "PNG" && header.format != "JPEG") || double(header.width) * header.height > 1e6) return;
    kc::Image image;
    const bool decoded = header.format == "PNG"
                             ? kc::app::detail::decodePng(text, image, problem)
                             : kc::app::detail::decodeJpeg(text, int(header.width), int(header.height), image, problem);
    if (!decoded) {
      if (problem.empty()) __builtin_trap();
      return;
    }
    // A decoded picture has the header's size and a full RGBA buffer.
    if (image.width != header.width || image.height != header.height) __builtin_trap();
    if (image.rgba.size() != std::size_t(image.width) * std::size_t(image.height) * 4) __builtin_trap();
  });
}
