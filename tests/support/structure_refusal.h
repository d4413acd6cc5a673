#pragma once
// Test support: the message with which a structure file's text is refused for a cage at spacing h
// (empty when it is accepted), for the lines and rigid-region tests.

#include <string>

#include "kc/app/errors.h"
#include "kc/app/structure.h"

namespace kc::test {

inline std::string structureRefusal(const std::string& text, const Cage& cage, double h = 6.0) {
  try {
    app::checkStructure(app::structureFromJson(text, "s.json"), cage, h, "s.json");
  } catch (const app::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace kc::test
