#pragma once
/// Wall-clock time for the reports' timings (steady clock).

#include <chrono>

namespace kc {

/// Seconds since t0 (std::chrono::steady_clock).
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace kc
