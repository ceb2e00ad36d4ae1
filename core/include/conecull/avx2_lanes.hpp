// Four lanes of 3-vectors for the AVX2 paths (one pair or candidate per 64-bit lane), and the
// loads that fill them. Included by the .cpp files that define [[gnu::target("avx2")]] functions.
#pragma once

#include <cstddef>
#include <cstdint>

#include "conecull/avx2.hpp"

#if CONECULL_HAS_AVX2_PATH
namespace conecull {

struct Lanes3 {
    __m256d x, y, z;
};

[[gnu::target("avx2"), gnu::always_inline]] inline __m256d abs4(__m256d v) {
    return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
}

// The corners V[3 i[l]..] of the four lanes as x, y, z vectors: one masked row load per lane
// (three doubles; the mask keeps the last row from reading past V) and a 4 x 4 transpose.
[[gnu::target("avx2"), gnu::always_inline]] inline Lanes3 corners4(const double* V, const int32_t i[4]) {
    const __m256i three = _mm256_set_epi64x(0, -1, -1, -1);
    const __m256d r0 = _mm256_maskload_pd(V + 3 * static_cast<size_t>(i[0]), three);
    const __m256d r1 = _mm256_maskload_pd(V + 3 * static_cast<size_t>(i[1]), three);
    const __m256d r2 = _mm256_maskload_pd(V + 3 * static_cast<size_t>(i[2]), three);
    const __m256d r3 = _mm256_maskload_pd(V + 3 * static_cast<size_t>(i[3]), three);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);  // x0 x1 z0 z1, y0 y1 . .
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    return {_mm256_permute2f128_pd(t0, t2, 0x20), _mm256_permute2f128_pd(t1, t3, 0x20),
            _mm256_permute2f128_pd(t0, t2, 0x31)};
}

}  // namespace conecull
#endif
