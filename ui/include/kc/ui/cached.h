#pragma once
/// What the GUI recomputes only when what it depends on changed (geometry-central's
/// DependentQuantity): a value that changes carries a Version, and whatever is computed from it is
/// a Cached<T, Key> keyed by the versions (and other inputs) it was computed from.

#include <cstdint>
#include <optional>
#include <type_traits>
#include <utility>
#include <variant>

namespace kc::ui {

/// Which state of a value something was computed from: bump() at every change of the value.
/// Two versions are equal when no change happened between them.
class Version {
 public:
  void bump() { ++m_n; }
  /// How many changes there were (the automation reports it).
  std::uint64_t count() const { return m_n; }
  bool operator==(const Version&) const = default;

 private:
  std::uint64_t m_n = 0;
};

/// A value computed from a key (versions, sizes, flags — anything comparable with ==), kept with
/// that key: get() computes it only when the key differs from the one it was computed from, or
/// after invalidate(). T = std::monostate: a side effect done once per key (an upload).
template <class T, class Key>
class Cached {
 public:
  /// The value for `key`: compute() (returning T, or nothing when T is std::monostate) runs when
  /// the value is not current for `key`.
  template <class F>
  const T& get(const Key& key, F&& compute) {
    if (!current(key)) {
      if constexpr (std::is_void_v<std::invoke_result_t<F>>) std::forward<F>(compute)();
      else m_value = std::forward<F>(compute)();
      m_key = key;
    }
    return m_value;
  }
  /// Records `value` as computed from `key` (an effect that may fail records its key only when done).
  void set(const Key& key, T value = {}) {
    m_value = std::move(value);
    m_key = key;
  }
  /// True when the value was computed from `key` (and not invalidated since).
  bool current(const Key& key) const { return m_key && *m_key == key; }
  /// The key the value was computed from, or none.
  const std::optional<Key>& key() const { return m_key; }
  /// The last value computed (T{} before the first).
  const T& value() const { return m_value; }
  /// The next get() computes, whatever its key.
  void invalidate() { m_key.reset(); }

 private:
  T m_value{};
  std::optional<Key> m_key;
};

/// A side effect (an upload, a deform in place) done once per key.
template <class Key>
using CachedEffect = Cached<std::monostate, Key>;

}  // namespace kc::ui
