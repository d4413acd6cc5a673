// libFuzzer target: the image header check (PNG, JPEG, BMP, TIFF, WebP, PNM) and the size limits.
#include "fuzz_support.h"
#include "kc/app/image_header.h"
#include "kc/app/limits.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return kc::fuzz::runLoader(data, size, [](const std::string& text) {
    kc::app::ImageHeader header;
    std::string problem;
    if (!kc::app::readImageHeader(text, header, problem)) {
      if (problem.empty()) __builtin_trap();  // a refusal always says why
      return;
    }
    kc::app::checkImageSize(header.width, header.height, "fuzz.image", header.format + " image");
  });
}
