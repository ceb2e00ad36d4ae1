#include "conecull/elementary/triangles_apart.hpp"

#if defined(__x86_64__) || defined(__i386__)
#define CONECULL_HAS_AVX2_PATH 1
#include <immintrin.h>
#else
#define CONECULL_HAS_AVX2_PATH 0  // other CPUs: the portable path only
#endif

#include "conecull/predicates/orient.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

namespace {

// Plane (a, b, c) against d[0..2], excused[k]: d[k] is a corner of (a, b, c). True iff every
// other d[k] is proven strictly on one side (FilteredPlane's filter).
bool one_side_excused(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3 d[3], const bool excused[3]) {
    const FilteredPlane plane(a, b, c);
    bool pos = true, neg = true;
    for (int k = 0; k < 3; ++k) {
        double det, bound;
        plane.eval(d[k], det, bound);
        pos = pos && (excused[k] || det > bound);
        neg = neg && (excused[k] || -det > bound);
    }
    return pos || neg;
}

#if CONECULL_HAS_AVX2_PATH
// ---- AVX2: the four pairs side by side, one pair per 64-bit lane ---------------------------

struct Lanes3 {
    __m256d x, y, z;
};

[[gnu::target("avx2"), gnu::always_inline]] inline __m256d abs4(__m256d v) {
    return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
}

// one_side_excused per lane: FilteredPlane's operations in the same order.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d one_side_excused4(const Lanes3& a, const Lanes3& b,
                                                                              const Lanes3& c, const Lanes3 d[3],
                                                                              const __m256d excused[3]) {
    const __m256d bax = _mm256_sub_pd(b.x, a.x), bay = _mm256_sub_pd(b.y, a.y), baz = _mm256_sub_pd(b.z, a.z);
    const __m256d cax = _mm256_sub_pd(c.x, a.x), cay = _mm256_sub_pd(c.y, a.y), caz = _mm256_sub_pd(c.z, a.z);
    const __m256d m1 = _mm256_mul_pd(bay, caz), m2 = _mm256_mul_pd(baz, cay);
    const __m256d m3 = _mm256_mul_pd(baz, cax), m4 = _mm256_mul_pd(bax, caz);
    const __m256d m5 = _mm256_mul_pd(bax, cay), m6 = _mm256_mul_pd(bay, cax);
    const __m256d nx = _mm256_sub_pd(m1, m2), ny = _mm256_sub_pd(m3, m4), nz = _mm256_sub_pd(m5, m6);
    const __m256d px = _mm256_add_pd(abs4(m1), abs4(m2)), py = _mm256_add_pd(abs4(m3), abs4(m4)),
                  pz = _mm256_add_pd(abs4(m5), abs4(m6));
    const __m256d err = _mm256_set1_pd(kDet3ErrBound), sign = _mm256_set1_pd(-0.0);
    __m256d pos = _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), neg = pos;
    for (int k = 0; k < 3; ++k) {
        const __m256d dax = _mm256_sub_pd(d[k].x, a.x), day = _mm256_sub_pd(d[k].y, a.y),
                      daz = _mm256_sub_pd(d[k].z, a.z);
        const __m256d det =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, dax), _mm256_mul_pd(ny, day)), _mm256_mul_pd(nz, daz));
        const __m256d perm = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(px, abs4(dax)), _mm256_mul_pd(py, abs4(day))),
                                           _mm256_mul_pd(pz, abs4(daz)));
        const __m256d bound = _mm256_mul_pd(err, perm);
        pos = _mm256_and_pd(pos, _mm256_or_pd(excused[k], _mm256_cmp_pd(det, bound, _CMP_GT_OQ)));
        neg = _mm256_and_pd(neg, _mm256_or_pd(excused[k], _mm256_cmp_pd(_mm256_xor_pd(det, sign), bound, _CMP_GT_OQ)));
    }
    return _mm256_or_pd(pos, neg);
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

// Slot s of the four faces' rows (three int32 each) as one vector per slot: a 4 x 4 transpose.
[[gnu::target("avx2"), gnu::always_inline]] inline void face_ids4(const int32_t* F, const int32_t f[4], __m128i out[3]) {
    const __m128i three = _mm_set_epi32(0, -1, -1, -1);
    __m128i r[4];
    for (int l = 0; l < 4; ++l) r[l] = _mm_maskload_epi32(F + 3 * static_cast<size_t>(f[l]), three);
    const __m128i a = _mm_unpacklo_epi32(r[0], r[1]), b = _mm_unpacklo_epi32(r[2], r[3]);
    const __m128i c = _mm_unpackhi_epi32(r[0], r[1]), d = _mm_unpackhi_epi32(r[2], r[3]);
    out[0] = _mm_unpacklo_epi64(a, b);
    out[1] = _mm_unpackhi_epi64(a, b);
    out[2] = _mm_unpacklo_epi64(c, d);
}

// Lanes of `id` equal to one of o[0..2], widened to 64-bit lane masks.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d shared4(__m128i id, const __m128i o[3]) {
    const __m128i eq = _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi32(id, o[0]), _mm_cmpeq_epi32(id, o[1])),
                                    _mm_cmpeq_epi32(id, o[2]));
    return _mm256_castsi256_pd(_mm256_cvtepi32_epi64(eq));
}

[[gnu::target("avx2")]] uint32_t triangles_apart4_avx2(const double* V, const int32_t* F, const FacePair* pairs) {
    const int32_t fp[4] = {pairs[0].first, pairs[1].first, pairs[2].first, pairs[3].first};
    const int32_t fq[4] = {pairs[0].second, pairs[1].second, pairs[2].second, pairs[3].second};
    __m128i ip[3], iq[3];
    face_ids4(F, fp, ip);
    face_ids4(F, fq, iq);
    alignas(16) int32_t slot[6][4];
    for (int s = 0; s < 3; ++s) {
        _mm_store_si128(reinterpret_cast<__m128i*>(slot[s]), ip[s]);
        _mm_store_si128(reinterpret_cast<__m128i*>(slot[3 + s]), iq[s]);
    }
    Lanes3 P[3], Q[3];
    __m256d q_shared[3], p_shared[3];
    for (int s = 0; s < 3; ++s) {
        P[s] = corners4(V, slot[s]);
        Q[s] = corners4(V, slot[3 + s]);
        q_shared[s] = shared4(iq[s], ip);
        p_shared[s] = shared4(ip[s], iq);
    }
    const __m256d apart =
        _mm256_or_pd(one_side_excused4(P[0], P[1], P[2], Q, q_shared), one_side_excused4(Q[0], Q[1], Q[2], P, p_shared));
    return static_cast<uint32_t>(_mm256_movemask_pd(apart));
}

#endif  // CONECULL_HAS_AVX2_PATH

}  // namespace

uint32_t triangles_apart4_portable(const double* V, const int32_t* F, const FacePair* pairs) {
    uint32_t bits = 0;
    for (int l = 0; l < 4; ++l) {
        const int32_t* fp = F + 3 * static_cast<size_t>(pairs[l].first);
        const int32_t* fq = F + 3 * static_cast<size_t>(pairs[l].second);
        const Vec3 P[3] = {load(V, fp[0]), load(V, fp[1]), load(V, fp[2])};
        const Vec3 Q[3] = {load(V, fq[0]), load(V, fq[1]), load(V, fq[2])};
        bool q_shared[3], p_shared[3];
        for (int k = 0; k < 3; ++k) {
            q_shared[k] = fq[k] == fp[0] || fq[k] == fp[1] || fq[k] == fp[2];
            p_shared[k] = fp[k] == fq[0] || fp[k] == fq[1] || fp[k] == fq[2];
        }
        if (one_side_excused(P[0], P[1], P[2], Q, q_shared) || one_side_excused(Q[0], Q[1], Q[2], P, p_shared))
            bits |= 1u << l;
    }
    return bits;
}

bool triangles_apart4_vectorised() {
#if CONECULL_HAS_AVX2_PATH
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2;
#else
    return false;
#endif
}

uint32_t triangles_apart4(const double* V, const int32_t* F, const FacePair* pairs) {
#if CONECULL_HAS_AVX2_PATH
    if (triangles_apart4_vectorised()) return triangles_apart4_avx2(V, F, pairs);
#endif
    return triangles_apart4_portable(V, F, pairs);
}

}  // namespace conecull
