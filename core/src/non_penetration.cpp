// The non-penetration filter four pairs at a time (ccd/non_penetration.hpp): the exact CCD
// query's loop over VF and EE pairs runs it ahead of each pair's full filter and test.
#include "conecull/ccd/non_penetration.hpp"

#include "conecull/avx2_lanes.hpp"

namespace conecull {

namespace {

// The four points of each lane's pair, by role: VF (v, a, b, c), EE (a, b, c, d).
template <bool kVf>
void points_of(const int32_t* prims, const uint64_t* keys, int32_t (&ids)[4][4]) {
    for (int l = 0; l < 4; ++l) {
        const auto hi = static_cast<int32_t>(keys[l] >> 32), lo = static_cast<int32_t>(keys[l] & 0xffffffffu);
        if constexpr (kVf) {
            ids[0][l] = hi;
            for (int k = 0; k < 3; ++k) ids[1 + k][l] = prims[3 * static_cast<size_t>(lo) + k];
        } else {
            ids[0][l] = prims[2 * static_cast<size_t>(hi)];
            ids[1][l] = prims[2 * static_cast<size_t>(hi) + 1];
            ids[2][l] = prims[2 * static_cast<size_t>(lo)];
            ids[3][l] = prims[2 * static_cast<size_t>(lo) + 1];
        }
    }
}

template <bool kVf>
uint32_t never_coplanar4_portable(const double* V0, const double* V1, const int32_t* prims, const uint64_t* keys) {
    int32_t ids[4][4];
    points_of<kVf>(prims, keys, ids);
    uint32_t bits = 0;
    for (int l = 0; l < 4; ++l) {
        Vec3 x0[4], x1[4];
        for (int k = 0; k < 4; ++k) x0[k] = load(V0, ids[k][l]), x1[k] = load(V1, ids[k][l]);
        DetRow r0[3], r1[3];
        if constexpr (kVf) {
            vf_rows(x0[0], x0[1], x0[2], x0[3], r0);
            vf_rows(x1[0], x1[1], x1[2], x1[3], r1);
        } else {
            ee_rows(x0[0], x0[1], x0[2], x0[3], r0);
            ee_rows(x1[0], x1[1], x1[2], x1[3], r1);
        }
        int s[4];
        filtered_coplanarity_signs(r0, r1, s);
        const int verdict = filtered_verdict(s);
        if (verdict > 0) bits |= 1u << l;
        if (verdict < 0) bits |= 16u << l;
    }
    return bits;
}

#if CONECULL_HAS_AVX2_PATH
// filtered_coplanarity_signs per lane, its operations in the same order.
[[gnu::target("avx2"), gnu::always_inline]] inline Lanes3 sub4(const Lanes3& a, const Lanes3& b) {
    return {_mm256_sub_pd(a.x, b.x), _mm256_sub_pd(a.y, b.y), _mm256_sub_pd(a.z, b.z)};
}
[[gnu::target("avx2"), gnu::always_inline]] inline Lanes3 add4(const Lanes3& a, const Lanes3& b) {
    return {_mm256_add_pd(a.x, b.x), _mm256_add_pd(a.y, b.y), _mm256_add_pd(a.z, b.z)};
}
struct Minor4 {
    Lanes3 v, a;
};
[[gnu::target("avx2"), gnu::always_inline]] inline Minor4 minor4(const Lanes3& q, const Lanes3& r) {
    const __m256d m1 = _mm256_mul_pd(q.y, r.z), m2 = _mm256_mul_pd(q.z, r.y);
    const __m256d m3 = _mm256_mul_pd(q.z, r.x), m4 = _mm256_mul_pd(q.x, r.z);
    const __m256d m5 = _mm256_mul_pd(q.x, r.y), m6 = _mm256_mul_pd(q.y, r.x);
    return {{_mm256_sub_pd(m1, m2), _mm256_sub_pd(m3, m4), _mm256_sub_pd(m5, m6)},
            {_mm256_add_pd(abs4(m1), abs4(m2)), _mm256_add_pd(abs4(m3), abs4(m4)), _mm256_add_pd(abs4(m5), abs4(m6))}};
}
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d dot4(const Lanes3& p, const Lanes3& x) {
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(p.x, x.x), _mm256_mul_pd(p.y, x.y)), _mm256_mul_pd(p.z, x.z));
}
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d abs_dot4(const Lanes3& p, const Lanes3& a) {
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(abs4(p.x), a.x), _mm256_mul_pd(abs4(p.y), a.y)),
                         _mm256_mul_pd(abs4(p.z), a.z));
}

template <bool kVf>
[[gnu::target("avx2")]] uint32_t never_coplanar4_avx2(const double* V0, const double* V1, const int32_t* prims,
                                                     const uint64_t* keys) {
    int32_t ids[4][4];
    points_of<kVf>(prims, keys, ids);
    Lanes3 x0[4], x1[4];
    for (int k = 0; k < 4; ++k) x0[k] = corners4(V0, ids[k]), x1[k] = corners4(V1, ids[k]);
    Lanes3 p0, q0, r0, p1, q1, r1;
    if constexpr (kVf) {
        p0 = sub4(x0[2], x0[1]), q0 = sub4(x0[3], x0[1]), r0 = sub4(x0[0], x0[1]);
        p1 = sub4(x1[2], x1[1]), q1 = sub4(x1[3], x1[1]), r1 = sub4(x1[0], x1[1]);
    } else {
        p0 = sub4(x0[1], x0[0]), q0 = sub4(x0[3], x0[2]), r0 = sub4(x0[2], x0[0]);
        p1 = sub4(x1[1], x1[0]), q1 = sub4(x1[3], x1[2]), r1 = sub4(x1[2], x1[0]);
    }
    const Minor4 A = minor4(q0, r0), B = minor4(q1, r0), C = minor4(q0, r1), D = minor4(q1, r1);
    const Lanes3 S = add4(B.v, C.v), Sa = add4(B.a, C.a);
    const __m256d k1 = _mm256_set1_pd(detail::kNpfBound1), k3 = _mm256_set1_pd(detail::kNpfBound3);
    const __m256d c[4] = {dot4(p0, A.v), _mm256_add_pd(dot4(p1, A.v), dot4(p0, S)),
                          _mm256_add_pd(dot4(p1, S), dot4(p0, D.v)), dot4(p1, D.v)};
    const __m256d b[4] = {_mm256_mul_pd(k1, abs_dot4(p0, A.a)),
                          _mm256_mul_pd(k3, _mm256_add_pd(abs_dot4(p1, A.a), abs_dot4(p0, Sa))),
                          _mm256_mul_pd(k3, _mm256_add_pd(abs_dot4(p1, Sa), abs_dot4(p0, D.a))),
                          _mm256_mul_pd(k1, abs_dot4(p1, D.a))};
    // value > bound (positive proven), -value > bound (negative proven): all four of one kind.
    const __m256d neg0 = _mm256_set1_pd(-0.0);
    // all_*: every coefficient proven of that sign; any_*: some coefficient.
    __m256d all_pos = _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), all_neg = all_pos;
    __m256d any_pos = _mm256_setzero_pd(), any_neg = any_pos;
    for (int k = 0; k < 4; ++k) {
        const __m256d pos = _mm256_cmp_pd(c[k], b[k], _CMP_GT_OQ);
        const __m256d neg = _mm256_cmp_pd(_mm256_xor_pd(c[k], neg0), b[k], _CMP_GT_OQ);
        all_pos = _mm256_and_pd(all_pos, pos), all_neg = _mm256_and_pd(all_neg, neg);
        any_pos = _mm256_or_pd(any_pos, pos), any_neg = _mm256_or_pd(any_neg, neg);
    }
    return static_cast<uint32_t>(_mm256_movemask_pd(_mm256_or_pd(all_pos, all_neg))) |
           static_cast<uint32_t>(_mm256_movemask_pd(_mm256_and_pd(any_pos, any_neg))) << 4;
}
#endif

}  // namespace

bool never_coplanar4_vectorised() { return cpu_has_avx2(); }

uint32_t vf_never_coplanar4_portable(const double* V0, const double* V1, const int32_t* F, const uint64_t* keys) {
    return never_coplanar4_portable<true>(V0, V1, F, keys);
}
uint32_t ee_never_coplanar4_portable(const double* V0, const double* V1, const int32_t* E, const uint64_t* keys) {
    return never_coplanar4_portable<false>(V0, V1, E, keys);
}
uint32_t vf_never_coplanar4(const double* V0, const double* V1, const int32_t* F, const uint64_t* keys) {
#if CONECULL_HAS_AVX2_PATH
    if (never_coplanar4_vectorised()) return never_coplanar4_avx2<true>(V0, V1, F, keys);
#endif
    return never_coplanar4_portable<true>(V0, V1, F, keys);
}
uint32_t ee_never_coplanar4(const double* V0, const double* V1, const int32_t* E, const uint64_t* keys) {
#if CONECULL_HAS_AVX2_PATH
    if (never_coplanar4_vectorised()) return never_coplanar4_avx2<false>(V0, V1, E, keys);
#endif
    return never_coplanar4_portable<false>(V0, V1, E, keys);
}

}  // namespace conecull
