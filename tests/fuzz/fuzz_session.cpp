// libFuzzer target: the session loader (every field, the cost checks, the kernel factorization).
#include "fuzz_support.h"
#include "kc/app/file_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return kc::fuzz::runLoader(data, size, [](const std::string& text) { kc::app::sessionFromJson(text, "fuzz.kcw.json"); });
}
