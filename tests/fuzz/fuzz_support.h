#pragma once
// Shared by the libFuzzer targets: run one loader on the input and accept only the error
// channel of bad input (kc::app::InputError, std::invalid_argument). Anything else escaping —
// another exception, a crash, a sanitizer report, a hang — is a finding.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "kc/app/errors.h"

namespace kc::fuzz {

template <class F>
int runLoader(const std::uint8_t* data, std::size_t size, F&& load) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    load(text);
  } catch (const kc::app::InputError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

}  // namespace kc::fuzz
