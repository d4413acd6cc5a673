#pragma once
/// printf-style formatting into a std::string, for the messages and reports kcwarp prints.

#include <cctype>
#include <cstdio>
#include <string>

namespace kc::app {

/// snprintf(fmt, args...) as a string (up to 511 characters; longer text is cut).
template <class... Args>
std::string format(const char* fmt, Args... args) {
  char text[512];
  std::snprintf(text, sizeof text, fmt, args...);
  return text;
}

/// A number in three significant digits ("%.3g"), as messages quote sizes and limits.
inline std::string shortNumber(double v) { return format("%.3g", v); }

/// `text` in upper case (ASCII), as the GUI names backends and methods ("KC", "QP").
inline std::string upperCase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace kc::app
