#pragma once
// Test support: the message a session file's load gives.

#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"

namespace kc::test {

/// Writes `j` to `path` and loads it: the InputError's message, or "(loaded without error)".
inline std::string loadError(const nlohmann::json& j, const std::string& path) {
  writeText(path, j.dump());
  try {
    app::loadSession(path);
  } catch (const app::InputError& e) {
    return e.what();
  }
  return "(loaded without error)";
}

}  // namespace kc::test
