// Deforming non-penetration filter (Tang et al. 2010, Sec. 5.1), the low-level culling of every
// VF and EE pair before its elementary CCD test: a contact needs the four points coplanar at some
// t in [0, 1]. With rows p(t), q(t), r(t) linear in t (each a difference head - tail of two
// linearly moving points), coplanarity is det[p(t); q(t); r(t)] = 0, a cubic in t. If its four
// Bernstein coefficients share one strict sign, it has no root on [0, 1]: no contact.
#pragma once

#include <cmath>
#include <cstdint>

#include "conecull/predicates/det_sum.hpp"

namespace conecull {

namespace detail {

// q x r and its permanent (|q_y r_z| + |q_z r_y|, ...): the rounded cross product is within a
// few eps of the exact one relative to the permanent.
struct Minor {
    Vec3 v, a;
};
[[gnu::always_inline]] inline Minor minor_of(const Vec3& q, const Vec3& r) {
    const double m1 = q.y * r.z, m2 = q.z * r.y, m3 = q.z * r.x, m4 = q.x * r.z, m5 = q.x * r.y, m6 = q.y * r.x;
    return {{m1 - m2, m3 - m4, m5 - m6},
            {std::fabs(m1) + std::fabs(m2), std::fabs(m3) + std::fabs(m4), std::fabs(m5) + std::fabs(m6)}};
}
[[gnu::always_inline]] inline double dot3(const Vec3& p, const Vec3& x) { return p.x * x.x + p.y * x.y + p.z * x.z; }
[[gnu::always_inline]] inline double abs_dot3(const Vec3& p, const Vec3& a) {
    return std::fabs(p.x) * a.x + std::fabs(p.y) * a.y + std::fabs(p.z) * a.z;
}
// The filter's bounds per unit of permanent (derivation at never_coplanar).
inline constexpr double kNpfBound1 = 9.0 * kEps, kNpfBound3 = 11.0 * kEps;
// 1 / -1 if `value`'s sign is proven by `bound`, else 0 (undecided: the exact sum decides).
[[gnu::always_inline]] inline int filtered_sign(double value, double bound) {
    return value > bound ? 1 : -value > bound ? -1 : 0;
}

}  // namespace detail

// The coplanarity cubic of rows e0 (at t = 0) and e1 (at t = 1). With p0, q0, r0 the rows of e0
// and p1, q1, r1 those of e1, det[p; q; r] = p . (q x r) is linear in each row, so the
// coefficients are (the inner two times 3, which keeps their signs)
//   c0 = det[p0; q0; r0]                                       = p0 . A
//   c1 = det[p1; q0; r0] + det[p0; q1; r0] + det[p0; q0; r1]   = p1 . A + p0 . (B + C)
//   c2 = det[p1; q1; r0] + det[p1; q0; r1] + det[p0; q1; r1]   = p1 . (B + C) + p0 . D
//   c3 = det[p1; q1; r1]                                       = p1 . D
// with A = q0 x r0, B = q1 x r0, C = q0 x r1, D = q1 x r1: four cross products shared by the eight
// determinants (checked against the determinants in tests/ccd/test_non_penetration.py).
//
// Filter. Every monomial (a product of three exact row differences) reaches the rounded c_k
// through at most 8 roundings in c0 and c3 (3 differences, the product and difference in the
// cross product, the product and two sums of the dot product) and 10 in c1 and c2 (one more for
// B + C, one for the final sum), so |rounded c_k - c_k| <= gamma_8 or gamma_10 times the sum of
// the monomials' magnitudes; the permanents computed here from the rounded rows are that sum
// within a factor 1 + 11 u. The bounds below, 9 u and 11 u times the rounded permanent (u =
// kEps = 2^-53, as det_sum_sign's (8 + m) u for m = 1 and 3 determinants), cover both with margin.
// No product under- or overflows for coordinates in [2^-128, 2^128] (the bindings' domain), so
// the relative bounds hold. A coefficient the filter cannot sign is summed exactly (det_sum_sign_exact).
//
// The filter's signs of c0..c3 (1, -1, or 0 where the bound cannot prove one), as above.
inline void filtered_coplanarity_signs(const DetRow (&e0)[3], const DetRow (&e1)[3], int (&s)[4]) {
    using namespace detail;
    const Vec3 p0 = e0[0].head - e0[0].tail, q0 = e0[1].head - e0[1].tail, r0 = e0[2].head - e0[2].tail;
    const Vec3 p1 = e1[0].head - e1[0].tail, q1 = e1[1].head - e1[1].tail, r1 = e1[2].head - e1[2].tail;
    const Minor A = minor_of(q0, r0), B = minor_of(q1, r0), C = minor_of(q0, r1), D = minor_of(q1, r1);
    const Vec3 S = B.v + C.v, Sa = B.a + C.a;
    s[0] = filtered_sign(dot3(p0, A.v), kNpfBound1 * abs_dot3(p0, A.a));
    s[1] = filtered_sign(dot3(p1, A.v) + dot3(p0, S), kNpfBound3 * (abs_dot3(p1, A.a) + abs_dot3(p0, Sa)));
    s[2] = filtered_sign(dot3(p1, S) + dot3(p0, D.v), kNpfBound3 * (abs_dot3(p1, Sa) + abs_dot3(p0, D.a)));
    s[3] = filtered_sign(dot3(p1, D.v), kNpfBound1 * abs_dot3(p1, D.a));
}

// What the filter's signs settle, a proven sign being the exact one: 1 never coplanar (all four
// proven, one sign), -1 not proven so (two proven of opposite signs), 0 undecided.
inline int filtered_verdict(const int (&s)[4]) {
    if (s[0] != 0 && s[1] == s[0] && s[2] == s[0] && s[3] == s[0]) return 1;
    const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0 || s[3] > 0;
    const bool neg = s[0] < 0 || s[1] < 0 || s[2] < 0 || s[3] < 0;
    return pos && neg ? -1 : 0;
}

// True if the cubic's four Bernstein coefficients have one strict sign (exactly decided).
inline bool never_coplanar(const DetRow (&e0)[3], const DetRow (&e1)[3]) {
    int s[4];
    filtered_coplanarity_signs(e0, e1, s);
    const int verdict = filtered_verdict(s);
    if (verdict != 0) return verdict > 0;
    const int s0 = s[0], s1 = s[1], s2 = s[2], s3 = s[3];
    const int any = s0 ? s0 : s1 ? s1 : s2 ? s2 : s3;  // the proven signs, all this one (or none)
    // Some coefficient is undecided (rare: the cubic nearly vanishes at an end or the rows nearly
    // coplanar): decide each undecided one exactly, from its determinants as listed above.
    const Det3 c0[1] = {{e0[0], e0[1], e0[2]}};
    const Det3 c1[3] = {{e1[0], e0[1], e0[2]}, {e0[0], e1[1], e0[2]}, {e0[0], e0[1], e1[2]}};
    const Det3 c2[3] = {{e1[0], e1[1], e0[2]}, {e1[0], e0[1], e1[2]}, {e0[0], e1[1], e1[2]}};
    const Det3 c3[1] = {{e1[0], e1[1], e1[2]}};
    const int e_0 = s0 ? s0 : detail::det_sum_sign_exact(c0, 1);
    if (e_0 == 0 || (any && e_0 != any)) return false;
    const int e_3 = s3 ? s3 : detail::det_sum_sign_exact(c3, 1);
    if (e_3 != e_0) return false;
    const int e_1 = s1 ? s1 : detail::det_sum_sign_exact(c1, 3);
    if (e_1 != e_0) return false;
    const int e_2 = s2 ? s2 : detail::det_sum_sign_exact(c2, 3);
    return e_2 == e_0;
}

// The rows of a vertex-face pair, vertex v against triangle (a, b, c): coplanar when
// det[b - a; c - a; v - a] = 0.
inline void vf_rows(const Vec3& v, const Vec3& a, const Vec3& b, const Vec3& c, DetRow (&e)[3]) {
    e[0] = {b, a}, e[1] = {c, a}, e[2] = {v, a};
}
// Of an edge-edge pair, edge (a, b) against edge (c, d): coplanar when det[b - a; d - c; c - a] = 0.
inline void ee_rows(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, DetRow (&e)[3]) {
    e[0] = {b, a}, e[1] = {d, c}, e[2] = {c, a};
}

// The filter on a vertex-face pair at t = 0 and t = 1.
inline bool vf_never_coplanar(const Vec3& v0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& v1,
                              const Vec3& a1, const Vec3& b1, const Vec3& c1) {
    DetRow e0[3], e1[3];
    vf_rows(v0, a0, b0, c0, e0);
    vf_rows(v1, a1, b1, c1, e1);
    return never_coplanar(e0, e1);
}

// On an edge-edge pair.
inline bool ee_never_coplanar(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                              const Vec3& b1, const Vec3& c1, const Vec3& d1) {
    DetRow e0[3], e1[3];
    ee_rows(a0, b0, c0, d0, e0);
    ee_rows(a1, b1, c1, d1, e1);
    return never_coplanar(e0, e1);
}

// Four pairs at a time, the floating-point filter only, from filtered_coplanarity_signs bit for
// bit (the AVX2 path does the same operations in the same order, without FMA: avx2.hpp): bit l
// (l < 4) set if pair l is proven never coplanar (never_coplanar is true), bit 4 + l if two of
// its coefficients are proven of opposite signs (never_coplanar is false, no exact sum needed).
// Neither: never_coplanar's exact part decides. VF keys are v << 32 | f (faces F, (m, 3)); EE keys ea << 32 | eb
// (edges E, (k, 2)); V0, V1 the positions at t = 0 and t = 1. AVX2 where the CPU has it.
uint32_t vf_never_coplanar4(const double* V0, const double* V1, const int32_t* F, const uint64_t* keys);
uint32_t ee_never_coplanar4(const double* V0, const double* V1, const int32_t* E, const uint64_t* keys);
// The same one lane at a time (for the tests: both paths must agree).
uint32_t vf_never_coplanar4_portable(const double* V0, const double* V1, const int32_t* F, const uint64_t* keys);
uint32_t ee_never_coplanar4_portable(const double* V0, const double* V1, const int32_t* E, const uint64_t* keys);
bool never_coplanar4_vectorised();

}  // namespace conecull
