#pragma once
// Private to kc::core's per-sample solvers: two-lane double vectors (GCC/Clang vector extensions;
// SSE2 on x86-64, NEON on ARM). The solvers' inner loops are floating-point reductions, which the
// compiler does not vectorize by itself.

#include <cstring>

namespace kc::detail {

using D2 = double __attribute__((vector_size(16)));

inline D2 load2(const double* p) {
  D2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline void store2(double* p, D2 v) { std::memcpy(p, &v, sizeof v); }

}  // namespace kc::detail
