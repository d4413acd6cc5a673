#pragma once
// Private to core/lbc: the ADMM loops' vector code. KC_VECTOR_CLONES compiles a function twice on
// x86-64, for AVX2 and for the baseline (SSE2), and picks one when the program loads (GCC's
// target_clones); without FMA, so both clones round every operation the same way and the results
// do not depend on the machine. D4 is a four-lane double vector (GCC/Clang vector
// extensions; the baseline clone lowers it to two-lane operations) for loops the compiler does
// not vectorize by itself.

#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#define KC_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define KC_VECTOR_CLONES
#endif

namespace kc::detail {

// Loaded and stored with std::memcpy (any alignment); two lanes: weights/simd2.h.
using D4 = double __attribute__((vector_size(32)));

}  // namespace kc::detail
