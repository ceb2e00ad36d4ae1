// The AVX2 paths' switch: compiled on x86 (functions marked [[gnu::target("avx2")]], no FMA, so
// their numbers are the portable paths' bit for bit), taken only where the CPU has AVX2.
#pragma once

#if defined(__x86_64__) || defined(__i386__)
#define CONECULL_HAS_AVX2_PATH 1
#include <immintrin.h>
#else
#define CONECULL_HAS_AVX2_PATH 0  // other CPUs: the portable paths only
#endif

namespace conecull {

inline bool cpu_has_avx2() {
#if CONECULL_HAS_AVX2_PATH
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2;
#else
    return false;
#endif
}

}  // namespace conecull
