// libFuzzer target: the points CSV reader of `kcwarp-cli eval`.
#include "fuzz_support.h"
#include "kc/app/points_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return kc::fuzz::runLoader(data, size, [](const std::string& text) { kc::app::parsePointsCsv(text, "fuzz.csv"); });
}
