#pragma once
/// One mechanism for the names of enum values in files, on the command line and in the GUI
/// (ARCHITECTURE.md lists them): each such enum specializes EnumNames next to its declaration
/// with a table of (value, name) pairs; toString, parseName and nameList read that table.

#include <array>
#include <string>
#include <string_view>
#include <utility>

namespace kc {

/// Specialized for each named enum E:
///   template <> struct EnumNames<E> {
///     static constexpr std::array<std::pair<E, std::string_view>, N> table{{{E::A, "a"}, ...}};
///   };
template <class E>
struct EnumNames;

template <class E>
concept NamedEnum = requires { EnumNames<E>::table; };

/// The name of e ("unknown" for a value missing from the table).
template <NamedEnum E>
constexpr std::string_view toString(E e) {
  for (const auto& [value, name] : EnumNames<E>::table)
    if (value == e) return name;
  return "unknown";
}

/// Sets e to the value named `text`; false (e untouched) when no value has that name.
template <NamedEnum E>
constexpr bool parseName(std::string_view text, E& e) {
  for (const auto& [value, name] : EnumNames<E>::table)
    if (name == text) {
      e = value;
      return true;
    }
  return false;
}

/// All names in table order, comma separated: "qp, qec, l1" (for "accepted: ..." messages).
template <NamedEnum E>
std::string nameList() {
  std::string list;
  for (const auto& [value, name] : EnumNames<E>::table) {
    if (!list.empty()) list += ", ";
    list += name;
  }
  return list;
}

}  // namespace kc
