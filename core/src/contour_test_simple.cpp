// The simplicity test's one-pose pass (contour_test_simple.hpp), four vertices at a time on AVX2.
#include "conecull/contour/contour_test_simple.hpp"

#include "conecull/avx2.hpp"

namespace conecull {

#if CONECULL_HAS_AVX2_PATH
namespace {

// Per lane, project_loop_gh_portable's operations in its order: d = p - c, X = (dx ux + dy uy) +
// dz uz (dot, vec3.hpp), the same for Y, |dx| + |dy| + |dz|, then Z.
[[gnu::target("avx2")]] double project_loop_gh_avx2(const int32_t* loop, const double* V, int32_t n, const Vec3& c,
                                                    const ProjectionFrame& f, double* zg, double* zh) {
    const __m256d cx = _mm256_set1_pd(c.x), cy = _mm256_set1_pd(c.y), cz = _mm256_set1_pd(c.z);
    const __m256d ux = _mm256_set1_pd(f.u.x), uy = _mm256_set1_pd(f.u.y), uz = _mm256_set1_pd(f.u.z);
    const __m256d wx = _mm256_set1_pd(f.w.x), wy = _mm256_set1_pd(f.w.y), wz = _mm256_set1_pd(f.w.z);
    const __m256d ph = _mm256_set1_pd(kSimplicityPhi), sign = _mm256_set1_pd(-0.0);
    __m256d d1v = _mm256_setzero_pd();
    int32_t i = 0;
    for (; i + 4 <= n; i += 4) {
        // Row offsets 3 id in 64 bits: no overflow whatever the vertex count.
        const __m256i id = _mm256_cvtepi32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(loop + i)));
        const __m256i row = _mm256_add_epi64(id, _mm256_add_epi64(id, id));
        const __m256d dx = _mm256_sub_pd(_mm256_i64gather_pd(V, row, 8), cx);
        const __m256d dy = _mm256_sub_pd(_mm256_i64gather_pd(V + 1, row, 8), cy);
        const __m256d dz = _mm256_sub_pd(_mm256_i64gather_pd(V + 2, row, 8), cz);
        const __m256d x =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, ux), _mm256_mul_pd(dy, uy)), _mm256_mul_pd(dz, uz));
        const __m256d y =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, wx), _mm256_mul_pd(dy, wy)), _mm256_mul_pd(dz, wz));
        const __m256d a1 = _mm256_add_pd(_mm256_add_pd(_mm256_andnot_pd(sign, dx), _mm256_andnot_pd(sign, dy)),
                                         _mm256_andnot_pd(sign, dz));
        d1v = _mm256_max_pd(a1, d1v);  // max_into(d1, a1): a1 > d1 ? a1 : d1
        _mm256_storeu_pd(zg + i, _mm256_add_pd(x, _mm256_mul_pd(ph, y)));
        _mm256_storeu_pd(zh + i, _mm256_sub_pd(y, _mm256_mul_pd(ph, x)));
    }
    // The lanes' maxima (never NaN: sums of absolute values) in any order, then the rest.
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, d1v);
    const double d1 = project_loop_gh_range(loop, V, i, n, c, f, zg, zh,
                                            max_into(max_into(lanes[0], lanes[1]), max_into(lanes[2], lanes[3])));
    wrap_loop_gh(zg, zh, n);
    return d1;
}

// Per lane, least_turn_margin_portable's operations; min_into(acc, m) is m < acc ? m : acc, which
// is _mm256_min_pd(m, acc) (a NaN m leaves acc), and max_into(a, b) is _mm256_max_pd(b, a).
[[gnu::target("avx2")]] double least_turn_margin_avx2(const double* zg, const double* zh, int32_t n) {
    const __m256d sign = _mm256_set1_pd(-0.0);
    __m256d acc = _mm256_set1_pd(std::numeric_limits<double>::infinity());
    int32_t b = 1;
    for (; b + 4 <= n + 1; b += 4) {
        const __m256d gb = _mm256_loadu_pd(zg + b), hb = _mm256_loadu_pd(zh + b);
        const __m256d ag = _mm256_sub_pd(_mm256_loadu_pd(zg + b - 1), gb);
        const __m256d ah = _mm256_sub_pd(_mm256_loadu_pd(zh + b - 1), hb);
        const __m256d cg = _mm256_sub_pd(_mm256_loadu_pd(zg + b + 1), gb);
        const __m256d ch = _mm256_sub_pd(_mm256_loadu_pd(zh + b + 1), hb);
        const __m256d dot = _mm256_add_pd(_mm256_mul_pd(ag, cg), _mm256_mul_pd(ah, ch));
        const __m256d cr = _mm256_sub_pd(_mm256_mul_pd(ag, ch), _mm256_mul_pd(ah, cg));
        const __m256d turn = _mm256_max_pd(_mm256_max_pd(_mm256_xor_pd(cr, sign), cr), _mm256_xor_pd(dot, sign));
        acc = _mm256_min_pd(turn, acc);
    }
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, acc);  // never NaN: started at infinity, and NaN turns leave it
    return least_turn_margin_range(zg, zh, b, n + 1,
                                   min_into(min_into(lanes[0], lanes[1]), min_into(lanes[2], lanes[3]))) +
           0.0;  // +0 for a zero, as the portable path
}

}  // namespace
#endif

bool simplicity_pass_vectorised() { return cpu_has_avx2(); }

double project_loop_gh(const int32_t* loop, const double* V, int32_t n, const Vec3& c, const ProjectionFrame& f,
                       double* zg, double* zh) {
#if CONECULL_HAS_AVX2_PATH
    if (simplicity_pass_vectorised()) return project_loop_gh_avx2(loop, V, n, c, f, zg, zh);
#endif
    return project_loop_gh_portable(loop, V, n, c, f, zg, zh);
}

double least_turn_margin(const double* zg, const double* zh, int32_t n) {
#if CONECULL_HAS_AVX2_PATH
    if (simplicity_pass_vectorised()) return least_turn_margin_avx2(zg, zh, n);
#endif
    return least_turn_margin_portable(zg, zh, n);
}

}  // namespace conecull
