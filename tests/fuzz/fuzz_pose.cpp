// libFuzzer target: the pose loader against a 4-point cage (both forms, counts, ranges).
#include "fuzz_support.h"
#include "kc/app/file_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const kc::Points C = (kc::Points(4, 2) << 16, 16, 80, 16, 80, 80, 16, 80).finished();
  return kc::fuzz::runLoader(data, size, [](const std::string& text) { kc::app::poseFromJson(text, C, "fuzz.pose.json"); });
}
