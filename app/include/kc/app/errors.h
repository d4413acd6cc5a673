#pragma once
/// The app layer's error channel for files and user input (STYLE.md, "Errors"): an InputError
/// names the file (or argument) and the problem in one line; the CLI maps it to exit code 2.
/// Anything else that escapes (std::invalid_argument included: a lower layer rejecting what the
/// app itself passed) is an internal failure, exit code 1.

#include <stdexcept>
#include <string>

namespace kc::app {

class InputError : public std::runtime_error {
 public:
  /// where: a file path or an argument name; what: the problem, e.g. "missing key 'points'".
  InputError(const std::string& where, const std::string& what) : std::runtime_error(where + ": " + what) {}
};

/// Returns f(), where f hands user data (a cage, a spacing) to a lower layer: that layer's
/// std::invalid_argument becomes an InputError naming `where`.
template <class F>
decltype(auto) asUserInput(const std::string& where, F&& f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw InputError(where, e.what());
  }
}

}  // namespace kc::app
