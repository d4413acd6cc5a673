#pragma once
/// The app layer's error channel for files and user input (STYLE.md, "Errors"): an InputError
/// names the file (or argument) and the problem in one line; the CLI maps it to exit code 2.

#include <stdexcept>
#include <string>

namespace kc::app {

class InputError : public std::runtime_error {
 public:
  /// where: a file path or an argument name; what: the problem, e.g. "missing key 'points'".
  InputError(const std::string& where, const std::string& what) : std::runtime_error(where + ": " + what) {}
};

}  // namespace kc::app
