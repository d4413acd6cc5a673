// libFuzzer target: the cage loader (JSON parse, shape checks, validateCage).
#include "fuzz_support.h"
#include "kc/app/file_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return kc::fuzz::runLoader(data, size, [](const std::string& text) { kc::app::cageFromJson(text, "fuzz.cage.json"); });
}
