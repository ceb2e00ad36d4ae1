#include "conecull/elementary/triangles_apart.hpp"

#include "conecull/avx2_lanes.hpp"

#include "conecull/elementary/triangle_triangle.hpp"
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

// FilteredPlane per lane, its operations in the same order.
struct Plane4 {
    __m256d ax, ay, az, nx, ny, nz, px, py, pz;
};

[[gnu::target("avx2"), gnu::always_inline]] inline Plane4 plane4(const Lanes3& a, const Lanes3& b, const Lanes3& c) {
    const __m256d bax = _mm256_sub_pd(b.x, a.x), bay = _mm256_sub_pd(b.y, a.y), baz = _mm256_sub_pd(b.z, a.z);
    const __m256d cax = _mm256_sub_pd(c.x, a.x), cay = _mm256_sub_pd(c.y, a.y), caz = _mm256_sub_pd(c.z, a.z);
    const __m256d m1 = _mm256_mul_pd(bay, caz), m2 = _mm256_mul_pd(baz, cay);
    const __m256d m3 = _mm256_mul_pd(baz, cax), m4 = _mm256_mul_pd(bax, caz);
    const __m256d m5 = _mm256_mul_pd(bax, cay), m6 = _mm256_mul_pd(bay, cax);
    return {a.x,
            a.y,
            a.z,
            _mm256_sub_pd(m1, m2),
            _mm256_sub_pd(m3, m4),
            _mm256_sub_pd(m5, m6),
            _mm256_add_pd(abs4(m1), abs4(m2)),
            _mm256_add_pd(abs4(m3), abs4(m4)),
            _mm256_add_pd(abs4(m5), abs4(m6))};
}

// FilteredPlane::eval per lane: lanes where d is proven strictly above (`pos`) or below (`neg`)
// the plane, i.e. orient3d(a, b, c, d) proven +1 or -1.
[[gnu::target("avx2"), gnu::always_inline]] inline void eval4(const Plane4& pl, const Lanes3& d, __m256d& pos,
                                                              __m256d& neg) {
    const __m256d dax = _mm256_sub_pd(d.x, pl.ax), day = _mm256_sub_pd(d.y, pl.ay), daz = _mm256_sub_pd(d.z, pl.az);
    const __m256d det =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(pl.nx, dax), _mm256_mul_pd(pl.ny, day)), _mm256_mul_pd(pl.nz, daz));
    const __m256d perm = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(pl.px, abs4(dax)), _mm256_mul_pd(pl.py, abs4(day))),
                                       _mm256_mul_pd(pl.pz, abs4(daz)));
    const __m256d bound = _mm256_mul_pd(_mm256_set1_pd(kDet3ErrBound), perm);
    pos = _mm256_cmp_pd(det, bound, _CMP_GT_OQ);
    neg = _mm256_cmp_pd(_mm256_xor_pd(det, _mm256_set1_pd(-0.0)), bound, _CMP_GT_OQ);
}

// one_side_excused per lane; gt[k], lt[k]: the lanes where d[k]'s sign is proven +1, -1.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d one_side_excused4(const Lanes3& a, const Lanes3& b,
                                                                              const Lanes3& c, const Lanes3 d[3],
                                                                              const __m256d excused[3], __m256d gt[3],
                                                                              __m256d lt[3]) {
    const Plane4 pl = plane4(a, b, c);
    __m256d pos = _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), neg = pos;
    for (int k = 0; k < 3; ++k) {
        eval4(pl, d[k], gt[k], lt[k]);
        pos = _mm256_and_pd(pos, _mm256_or_pd(excused[k], gt[k]));
        neg = _mm256_and_pd(neg, _mm256_or_pd(excused[k], lt[k]));
    }
    return _mm256_or_pd(pos, neg);
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

// The four pairs' corners, which corners they share, and the plane rejection with its signs.
struct Block4 {
    Lanes3 P[3], Q[3];
    __m256d q_shared[3], p_shared[3];  // Q[k] is a corner of P; P[k] of Q
    __m256d q_gt[3], q_lt[3];          // orient3d(P, Q[k]) proven +1, -1
    __m256d p_gt[3], p_lt[3];          // orient3d(Q, P[k]) proven +1, -1
    uint32_t apart;                    // lanes the plane rejection settles
};

[[gnu::target("avx2"), gnu::always_inline]] inline void block4(const double* V, const int32_t* F,
                                                               const FacePair* pairs, Block4& b) {
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
    for (int s = 0; s < 3; ++s) {
        b.P[s] = corners4(V, slot[s]);
        b.Q[s] = corners4(V, slot[3 + s]);
        b.q_shared[s] = shared4(iq[s], ip);
        b.p_shared[s] = shared4(ip[s], iq);
    }
    const __m256d apart = _mm256_or_pd(one_side_excused4(b.P[0], b.P[1], b.P[2], b.Q, b.q_shared, b.q_gt, b.q_lt),
                                       one_side_excused4(b.Q[0], b.Q[1], b.Q[2], b.P, b.p_shared, b.p_gt, b.p_lt));
    b.apart = static_cast<uint32_t>(_mm256_movemask_pd(apart));
}

[[gnu::target("avx2")]] uint32_t triangles_apart4_avx2(const double* V, const int32_t* F, const FacePair* pairs) {
    Block4 b;
    block4(V, F, pairs, b);
    return b.apart;
}

[[gnu::target("avx2"), gnu::always_inline]] inline uint32_t bits(__m256d m) {
    return static_cast<uint32_t>(_mm256_movemask_pd(m));
}
// 4-bit lane set -> lane mask.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256d lanes(uint32_t set) {
    const __m256i bit = _mm256_and_si256(_mm256_set1_epi64x(set), _mm256_set_epi64x(8, 4, 2, 1));
    return _mm256_castsi256_pd(_mm256_cmpeq_epi64(bit, _mm256_set_epi64x(8, 4, 2, 1)));
}
[[gnu::target("avx2"), gnu::always_inline]] inline Lanes3 select3(__m256d m, const Lanes3& yes, const Lanes3& no) {
    return {_mm256_blendv_pd(no.x, yes.x, m), _mm256_blendv_pd(no.y, yes.y, m), _mm256_blendv_pd(no.z, yes.z, m)};
}

// The corners of X (three lanes each) rotated to start at the lone corner in `lone` (lone[k]:
// the lanes where it is X[k]), then the last two swapped in the lanes of `swap`.
[[gnu::target("avx2"), gnu::always_inline]] inline void rotate4(const Lanes3 X[3], const uint32_t lone[3],
                                                                uint32_t swap, Lanes3 out[3]) {
    const __m256d l0 = lanes(lone[0]), l1 = lanes(lone[1]);
    out[0] = select3(l0, X[0], select3(l1, X[1], X[2]));
    Lanes3 second = select3(l0, X[1], select3(l1, X[2], X[0]));
    Lanes3 third = select3(l0, X[2], select3(l1, X[0], X[1]));
    const __m256d sw = lanes(swap);
    out[1] = select3(sw, third, second);
    out[2] = select3(sw, second, third);
}

// lone[k]: the lanes where corner k alone has its sign (pos[k]: the lanes where it is +1), for
// three non-zero signs not all alike (lone_corner of triangle_triangle.cpp).
inline void lone_corners(const uint32_t pos[3], uint32_t lone[3]) {
    lone[0] = ~(pos[1] ^ pos[2]) & (pos[0] ^ pos[1]) & 15u;
    lone[1] = ~(pos[0] ^ pos[2]) & (pos[1] ^ pos[0]) & 15u;
    lone[2] = ~(pos[0] ^ pos[1]) & (pos[2] ^ pos[0]) & 15u;
}

// triangles_collide for the four pairs, from the block's signs where they decide (`decided`
// gets those lanes), as triangles_collide's generic cases:
// - lanes apart: no;
// - one shared corner, every other sign proven (so a, b straddle Q's plane and c, d P's):
//   collide_shared_vertex's last step, yes iff sign(a) != sign(c) for P = (v, a, b), Q = (v, c, d);
// - no shared corner, every sign proven: crossing_planes_meet, its two orient3d filtered here;
//   decided where both are proven, or one proves "no".
[[gnu::target("avx2")]] uint32_t triangles_collide4_avx2(const double* V, const int32_t* F, const FacePair* pairs,
                                                         uint32_t& decided) {
    Block4 b;
    block4(V, F, pairs, b);
    decided = b.apart;
    if (b.apart == 15u) return 0;
    uint32_t qg[3], pg[3], qs[3], ps[3];
    uint32_t known = 15u & ~b.apart;
    for (int k = 0; k < 3; ++k) {
        qg[k] = bits(b.q_gt[k]);
        pg[k] = bits(b.p_gt[k]);
        qs[k] = bits(b.q_shared[k]);
        ps[k] = bits(b.p_shared[k]);
        known &= (qg[k] | bits(b.q_lt[k]) | qs[k]) & (pg[k] | bits(b.p_lt[k]) | ps[k]);
    }
    uint32_t hits = 0;
    const uint32_t any_shared = ps[0] | ps[1] | ps[2];
    // Exactly one corner of each is shared (a face listing a vertex twice goes to triangles_collide).
    const auto exactly_one = [](const uint32_t x[3]) { return (x[0] ^ x[1] ^ x[2]) & ~(x[0] & x[1] & x[2]); };
    const uint32_t one_shared = exactly_one(ps) & exactly_one(qs);
    if (const uint32_t sv = known & one_shared; sv != 0) {
        // a = P[i + 1] for the shared P[i], c = Q[j + 1] for the shared Q[j].
        uint32_t a_pos = 0, c_pos = 0;
        for (int k = 0; k < 3; ++k) {
            a_pos |= ps[k] & pg[(k + 1) % 3];
            c_pos |= qs[k] & qg[(k + 1) % 3];
        }
        hits |= sv & (a_pos ^ c_pos);
        decided |= sv;
    }
    if (const uint32_t ns = known & ~any_shared & 15u; ns != 0) {
        uint32_t lp[3], lq[3];
        lone_corners(pg, lp);  // P's lone corner against Q's plane
        lone_corners(qg, lq);
        // crossing_planes_meet: swap q2, q3 where oq[lp] < 0, p2, p3 where op[lq] < 0.
        const uint32_t p_lone_neg = ((lp[0] & ~pg[0]) | (lp[1] & ~pg[1]) | (lp[2] & ~pg[2])) & 15u;
        const uint32_t q_lone_neg = ((lq[0] & ~qg[0]) | (lq[1] & ~qg[1]) | (lq[2] & ~qg[2])) & 15u;
        Lanes3 p[3], q[3];
        rotate4(b.P, lp, q_lone_neg, p);
        rotate4(b.Q, lq, p_lone_neg, q);
        // yes iff orient3d(p1, p2, q1, q2) <= 0 and orient3d(p1, p3, q1, q3) >= 0.
        __m256d pos1, neg1, pos2, neg2;
        eval4(plane4(p[0], p[1], q[0]), q[1], pos1, neg1);
        eval4(plane4(p[0], p[2], q[0]), q[2], pos2, neg2);
        const uint32_t yes = bits(_mm256_and_pd(neg1, pos2)), no = bits(_mm256_or_pd(pos1, neg2));
        hits |= ns & yes;
        decided |= ns & (yes | no);
    }
    return hits;
}

#endif  // CONECULL_HAS_AVX2_PATH

}  // namespace

bool triangles_collide_rows(const double* V, const int32_t* F, const FacePair& pair) {
    const int32_t* fp = F + 3 * static_cast<size_t>(pair.first);
    const int32_t* fq = F + 3 * static_cast<size_t>(pair.second);
    const Vec3 P[3] = {load(V, fp[0]), load(V, fp[1]), load(V, fp[2])};
    const Vec3 Q[3] = {load(V, fq[0]), load(V, fq[1]), load(V, fq[2])};
    return triangles_collide(fp, P, fq, Q);
}

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

uint32_t triangles_collide4_portable(const double* V, const int32_t* F, const FacePair* pairs) {
    const uint32_t apart = triangles_apart4_portable(V, F, pairs);
    uint32_t hits = 0;
    for (int l = 0; l < 4; ++l)
        if (!(apart >> l & 1) && triangles_collide_rows(V, F, pairs[l])) hits |= 1u << l;
    return hits;
}

bool triangles_apart4_vectorised() { return cpu_has_avx2(); }

uint32_t triangles_apart4(const double* V, const int32_t* F, const FacePair* pairs) {
#if CONECULL_HAS_AVX2_PATH
    if (triangles_apart4_vectorised()) return triangles_apart4_avx2(V, F, pairs);
#endif
    return triangles_apart4_portable(V, F, pairs);
}

uint32_t triangles_collide4(const double* V, const int32_t* F, const FacePair* pairs) {
#if CONECULL_HAS_AVX2_PATH
    if (triangles_apart4_vectorised()) {
        uint32_t decided = 0;
        uint32_t hits = triangles_collide4_avx2(V, F, pairs, decided);
        for (uint32_t rest = ~decided & 15u; rest != 0; rest &= rest - 1) {
            const int l = __builtin_ctz(rest);
            if (triangles_collide_rows(V, F, pairs[l])) hits |= 1u << l;
        }
        return hits;
    }
#endif
    return triangles_collide4_portable(V, F, pairs);
}

}  // namespace conecull
