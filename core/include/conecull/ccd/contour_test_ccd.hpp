// Unprojected contour test for CCD (Sec. 3.6, Alg. 3): contour vertices move linearly from
// V0 to V1 over t in [0, 1]; the axis l stays fixed.
//
// The kernel point moves too (a departure from the printed Alg. 3, which keeps o fixed): o(t)
// runs linearly from o0 to o1, by default the contour's mean at t = 0 and at t = 1, i.e. the
// mean at every t. The test proves, for every t, that the projection along l of the contour at
// t is a simple polygon, star-shaped around o(t); that is the DCD theorem at time t (Sec. 3.4),
// which holds for any point o(t), so the cone over [0, 1] and this test cull the node for the
// whole step. A fixed o fails whenever a node translates across the plane by more than its
// kernel's width during the step (measured on the funnel scene: most failing tests were the
// kernel sign or a vertex crossing the ray line, see README).
//
// CSide1(o, b, c, l) = ((b(t) - o(t)) x (c(t) - o(t))) . l is quadratic in t; with
// B_t = b_t - o_t, C_t = c_t - o_t (linear in t) its Bernstein coefficients are (derived here,
// checked against fractions in tests/ccd):
//     k0 = (B0 x C0) . l,   k1 = ((B0 x C1) + (B1 x C0)) . l / 2,   k2 = (B1 x C1) . l.
// (With o fixed, the printed k2 adds (v_c x (b0 - a)) . l; it must be (b0 - a) x v_c
// (= -(v_c x (b0 - a))): k2 is the value at t = 1.) CSideSign1 is s when all three have the
// strict sign s, else 0. CSide2 (the side of a moving vertex of the ray's line from o(t)) is
// linear in t: its signs at t = 0 and t = 1. Every sign is exact, so "passed" proves that at
// every t the projected contour is a simple star-shaped polygon around o(t).
#pragma once

#include <cstdint>
#include <utility>

#include "conecull/contour/contour_test.hpp"
#include "conecull/predicates/det_sum.hpp"

namespace conecull {

// CSideSign1(o, b, c, l) with o: o0 -> o1, b: b0 -> b1, c: c0 -> c1 (Alg. 3 lines 12, 19).
inline int csidesign1(const Vec3& o0, const Vec3& o1, const Vec3& b0, const Vec3& c0, const Vec3& b1, const Vec3& c1,
                      const Vec3& l) {
    // side_sign(a, b, c, l) = ((a - c) x (b - c)) . l = ((b - a) x (c - a)) . l with a = o.
    const int k0 = side_sign(o0, b0, c0, l);
    if (k0 == 0) return 0;
    const int k2 = side_sign(o1, b1, c1, l);
    if (k2 != k0) return 0;
    // sign(k1) = sign(det[l; B0; C1] + det[l; B1; C0])   ((u x w) . l = det[l; u; w])
    const Vec3 zero{};
    const Det3 d[2] = {{{l, zero}, {b0, o0}, {c1, o1}}, {{l, zero}, {b1, o1}, {c0, o0}}};
    const int k1 = det_sum_sign(d);
    return k1 == k0 ? k0 : 0;
}

// CSideSign2(v, o, o + r, l) with v: v0 -> v1, o: o0 -> o1 (Alg. 3 lines 23-24); see ray_side_sign.
inline int csidesign2(const Vec3& v0, const Vec3& v1, const Vec3& o0, const Vec3& o1, const Vec3& r, const Vec3& l) {
    const int s0 = ray_side_sign(v0, o0, r, l);
    if (s0 == 0) return 0;
    return ray_side_sign(v1, o1, r, l) == s0 ? s0 : 0;
}

struct ContinuousSigns {
    const int32_t* loop;
    const double* V0;
    const double* V1;
    Vec3 o0, o1, r, l;
    int kernel(int32_t i, int32_t j) const {  // Alg. 3 lines 12, 19
        return csidesign1(o0, o1, load(V0, loop[i]), load(V0, loop[j]), load(V1, loop[i]), load(V1, loop[j]), l);
    }
    int ray(int32_t i) const { return csidesign2(load(V0, loop[i]), load(V1, loop[i]), o0, o1, r, l); }  // lines 23-24
};

// Alg. 3 with the kernel point moving from o0 to o1 (o0 == o1: the printed, fixed o).
inline ContourVerdict unprojected_contour_test_ccd_with_ray(const int32_t* loop, int32_t n, const double* V0,
                                                          const double* V1, const Vec3& l, const Vec3& r,
                                                          const Vec3& o0, const Vec3& o1) {
    ContourVerdict out;
    out.kernel = o0;
    out.kernel_end = o1;
    out.ray = r;
    return star_contour_test(n, ContinuousSigns{loop, V0, V1, o0, o1, r, l}, out);
}

// Alg. 3 as printed: the kernel point the mean at t = 0 moving to the mean at t = 1.
inline ContourVerdict unprojected_contour_test_ccd_at_mean(const int32_t* loop, int32_t n, const double* V0,
                                                          const double* V1, const Vec3& l) {
    const Vec3 m0 = kernel_point(loop, n, V0), m1 = kernel_point(loop, n, V1);
    return with_ray_retry(
        l, [&](const Vec3& r) { return unprojected_contour_test_ccd_with_ray(loop, n, V0, V1, l, r, m0, m1); });
}

// If the means fail the kernel test, a kernel point of the loop at t = 0 moving to one of the
// loop at t = 1 (find_kernel_point at each end). At t = 0 and t = 1 the retry's o is in the
// kernel whenever the kernel polygons are proper; in between, the test decides with exact signs.
// `v` is the verdict at the means (v.kernel, v.kernel_end).
inline ContourVerdict retry_kernel_point_ccd(ContourVerdict v, const int32_t* loop, int32_t n, const double* V0,
                                             const double* V1, const Vec3& l) {
    using Ends = std::pair<Vec3, Vec3>;  // o at t = 0 and at t = 1
    const Vec3 m0 = v.kernel, m1 = v.kernel_end;
    const auto find = [&](ProjectionScratch& s, Ends& o, int32_t& searched, int32_t edge) {
        int32_t searched0 = 0, searched1 = 0;
        const bool found = find_kernel_point(loop, n, V0, l, m0, s, o.first, searched0, edge) &&
                           find_kernel_point(loop, n, V1, l, m1, s, o.second, searched1, edge);
        searched = searched0 + searched1;
        return found;
    };
    const auto test = [&](const Ends& o) {
        return with_ray_retry(l, [&](const Vec3& r) {
            return unprojected_contour_test_ccd_with_ray(loop, n, V0, V1, l, r, o.first, o.second);
        });
    };
    return with_kernel_retry<Ends>(v, find, test);
}

inline ContourVerdict unprojected_contour_test_ccd(const int32_t* loop, int32_t n, const double* V0, const double* V1,
                                                  const Vec3& l) {
    return retry_kernel_point_ccd(unprojected_contour_test_ccd_at_mean(loop, n, V0, V1, l), loop, n, V0, V1, l);
}

}  // namespace conecull
