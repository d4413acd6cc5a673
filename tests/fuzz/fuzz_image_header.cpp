// libFuzzer target: the image header check (PNG, JPEG, BMP, TIFF, WebP, PNM) and the size limits,
// then, for a PNG that passes them, kcwarp's own PNG decoder (app/src/png_codec.cpp: libpng with
// setjmp error handling) — up to a million pixels, so a run stays fast.
#include "fuzz_support.h"
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
    if (header.format != "PNG" || double(header.width) * header.height > 1e6) return;
    kc::Image image;
    if (!kc::app::detail::decodePng(text, image, problem)) {
      if (problem.empty()) __builtin_trap();
      return;
    }
    // A decoded PNG has the header's size and a full RGBA buffer.
    if (image.width != header.width || image.height != header.height) __builtin_trap();
    if (image.rgba.size() != std::size_t(image.width) * std::size_t(image.height) * 4) __builtin_trap();
  });
}
