// Unprojected contour test for CCD (Sec. 3.6, Alg. 3): contour vertices move linearly from
// V0 to V1 over t in [0, 1]; the kernel point o (mean at t = 0) and the axis l stay fixed.
//
// CSide1(o, b, c, l) = ((b(t) - o) x (c(t) - o)) . l is quadratic in t; with B_t = b_t - o,
// C_t = c_t - o its Bernstein coefficients are (derived here, checked against fractions in
// tests/ccd):
//     k0 = (B0 x C0) . l,   k1 = ((B0 x C1) + (B1 x C0)) . l / 2,   k2 = (B1 x C1) . l.
// The printed k2 adds (v_c x (b0 - a)) . l; it must be (b0 - a) x v_c (= -(v_c x (b0 - a))):
// k2 is the value at t = 1. CSideSign1 is s when all three have the strict sign s, else 0.
// CSide2 (the ray side of a moving vertex) is linear in t: its signs at t = 0 and t = 1.
// Every sign is exact, so "passed" proves that at every t the projected contour is a simple
// star-shaped polygon around o.
#pragma once

#include <cstdint>

#include "conecull/contour/contour_test.hpp"
#include "conecull/predicates/det_sum.hpp"

namespace conecull {

// CSideSign1(o, b, c, l) with b: b0 -> b1, c: c0 -> c1 (Alg. 3 lines 12, 19).
inline int csidesign1(const Vec3& o, const Vec3& b0, const Vec3& c0, const Vec3& b1, const Vec3& c1, const Vec3& l) {
    // side_sign(a, b, c, l) = ((a - c) x (b - c)) . l = ((b - a) x (c - a)) . l with a = o.
    const int k0 = side_sign(o, b0, c0, l);
    if (k0 == 0) return 0;
    const int k2 = side_sign(o, b1, c1, l);
    if (k2 != k0) return 0;
    // sign(k1) = sign(det[l; B0; C1] + det[l; B1; C0])   ((u x w) . l = det[l; u; w])
    const Vec3 zero{};
    const Det3 d[2] = {{{l, zero}, {b0, o}, {c1, o}}, {{l, zero}, {b1, o}, {c0, o}}};
    const int k1 = det_sum_sign(d);
    return k1 == k0 ? k0 : 0;
}

// CSideSign2(v, o, o + r, l) with v: v0 -> v1 (Alg. 3 lines 23-24); see ray_side_sign.
inline int csidesign2(const Vec3& v0, const Vec3& v1, const Vec3& o, const Vec3& r, const Vec3& l) {
    const int s0 = ray_side_sign(v0, o, r, l);
    if (s0 == 0) return 0;
    return ray_side_sign(v1, o, r, l) == s0 ? s0 : 0;
}

struct ContinuousSigns {
    const int32_t* loop;
    const double* V0;
    const double* V1;
    Vec3 o, r, l;
    int kernel(int32_t i, int32_t j) const {  // Alg. 3 lines 12, 19
        return csidesign1(o, load(V0, loop[i]), load(V0, loop[j]), load(V1, loop[i]), load(V1, loop[j]), l);
    }
    int ray(int32_t i) const { return csidesign2(load(V0, loop[i]), load(V1, loop[i]), o, r, l); }  // lines 23-24
};

// Alg. 3 with kernel point o, fixed over the step.
inline ContourVerdict unprojected_contour_test_ccd_with_ray(const int32_t* loop, int32_t n, const double* V0,
                                                          const double* V1, const Vec3& l, const Vec3& r,
                                                          const Vec3& o) {
    ContourVerdict out;
    out.kernel = o;
    out.ray = r;
    return star_contour_test(n, ContinuousSigns{loop, V0, V1, o, r, l}, out);
}
// Alg. 3 line 2: the mean at t = 0.
inline ContourVerdict unprojected_contour_test_ccd_with_ray(const int32_t* loop, int32_t n, const double* V0,
                                                          const double* V1, const Vec3& l, const Vec3& r) {
    return unprojected_contour_test_ccd_with_ray(loop, n, V0, V1, l, r, kernel_point(loop, n, V0));
}

// The kernel point: the mean at t = 0, then, if that fails the kernel test, the line-search
// kernel point of the loop at t = 0 (with_kernel_retry); o stays fixed over the step.
inline ContourVerdict unprojected_contour_test_ccd(const int32_t* loop, int32_t n, const double* V0, const double* V1,
                                                  const Vec3& l) {
    return with_kernel_retry(loop, n, V0, l, [&](const Vec3& o) {
        return with_ray_retry(
            l, [&](const Vec3& r) { return unprojected_contour_test_ccd_with_ray(loop, n, V0, V1, l, r, o); });
    });
}

}  // namespace conecull
