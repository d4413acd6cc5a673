// libFuzzer target: the structure loader (JSON parse, line entries, the rigid refusal) and the
// lines' geometry checks against the bundled star's cage (validateLines).
#include "fuzz_support.h"
#include "kc/app/structure.h"

namespace {

kc::Cage starCage() {
  kc::Points C(10, 2);
  C << 160, 18, 197.6, 116.2, 302.7, 121.6, 220.9, 187.8, 248.2, 289.4, 160, 232, 71.8, 289.4, 99.1, 187.8, 17.3, 121.6,
      122.4, 116.2;
  return kc::Cage::polygon(C);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const kc::Cage cage = starCage();
  return kc::fuzz::runLoader(data, size, [](const std::string& text) {
    const kc::app::Structure st = kc::app::structureFromJson(text, "fuzz.structure.json");
    kc::app::checkStructure(st, cage, 6.0, "fuzz.structure.json");
  });
}
