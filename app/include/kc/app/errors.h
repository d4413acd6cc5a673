#pragma once
/// The app layer's error channel for files and user input (STYLE.md, "Errors"): an InputError
/// names the file (or argument) and the problem in one line; the CLI maps it to exit code 2.
/// Anything else that escapes (std::invalid_argument included: a lower layer rejecting what the
/// app itself passed) is an internal failure, exit code 1.
///
/// Every message is one line of bounded length: control characters (a newline in a path) are
/// written as escapes and each part is clipped (oneLine), so a message never echoes more than a
/// short excerpt of what a file or an argument held.

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace kc::app {

/// Longest `where` of an InputError (a path is kept by its head and tail), bytes.
inline constexpr std::size_t kMaxMessageWhere = 240;
/// Longest `what` of an InputError, bytes.
inline constexpr std::size_t kMaxMessageWhat = 480;

namespace detail {
/// `text` with control characters written as escapes (\n, \t, \xNN), stopping once the result
/// holds more than `cap` bytes.
inline std::string escapeControls(std::string_view text, std::size_t cap) {
  std::string s;
  for (const char c : text) {
    if (s.size() > cap) break;
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) s += c;
    else if (c == '\n') s += "\\n";
    else if (c == '\r') s += "\\r";
    else if (c == '\t') s += "\\t";
    else {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\x%02x", u);
      s += esc;
    }
  }
  return s;
}
/// True when byte c continues a UTF-8 character (cuts are moved off such bytes).
inline bool utf8Continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }
}  // namespace detail

/// `text` as one line of at most maxBytes + 5 bytes: control characters become escapes (\n, \t,
/// \xNN), and a longer text keeps its first two thirds and its end around " ... " (cut at UTF-8
/// character boundaries; ASCII dots, which every font draws).
inline std::string oneLine(std::string_view text, std::size_t maxBytes) {
  std::string s = detail::escapeControls(text, maxBytes);
  if (s.size() <= maxBytes) return s;
  std::size_t head = maxBytes * 2 / 3;
  while (head > 0 && detail::utf8Continuation(s[head])) --head;
  const std::size_t tailBytes = maxBytes - maxBytes * 2 / 3;
  std::string tail = detail::escapeControls(text.substr(text.size() - std::min(text.size(), tailBytes)), 4 * tailBytes);
  std::size_t t = tail.size() > tailBytes ? tail.size() - tailBytes : 0;
  while (t < tail.size() && detail::utf8Continuation(tail[t])) ++t;
  return s.substr(0, head) + " ... " + tail.substr(t);
}

class InputError : public std::runtime_error {
 public:
  /// where: a file path or an argument name; what: the problem, e.g. "missing key 'points'".
  /// Both are made one line and clipped (oneLine, kMaxMessageWhere / kMaxMessageWhat).
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(oneLine(where, kMaxMessageWhere) + ": " + oneLine(what, kMaxMessageWhat)) {}
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
