// Normal cones for CCD (Sec. 3.6): with every vertex moving linearly over t in [0, 1], a
// triangle's normal n(t) = e1(t) x e2(t) is quadratic in t. In Bernstein form
//     n(t) = (1-t)^2 n0 + 2t(1-t) n1 + t^2 n2,
//     n0 = e1(0) x e2(0),  n2 = e1(1) x e2(1),  n1 = (e1(0) x e2(1) + e1(1) x e2(0)) / 2,
// a non-negative combination of the three control normals, so a cone (half-angle < pi/2)
// holding all three holds n(t) for every t. Each control normal is widened by a rigorous
// bound on its rounding error, exactly as for DCD; a zero or unresolved one gives a full cone.
#pragma once

#include <cmath>

#include "conecull/cone/normal_cone.hpp"
#include "conecull/predicates/orient.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

// A control vector given as the sum of cross products sum_k (u_k x w_k) * scale, with u_k, w_k
// rounded differences (their error is accounted for like triangle_cone's), rounded, and the bound
// err on its rounding error.
inline Vec3 control_vector(const Vec3* u, const Vec3* w, int terms, double& err) {
    Vec3 n;
    double abs_products = 0.0;
    for (int k = 0; k < terms; ++k) n = n + rounded_cross(u[k], w[k], abs_products);
    // Per cross product the error is below 9 eps of its absolute products (triangle_cone);
    // summing up to two of them adds eps of the same; 12 eps keeps a margin. Scaling by 1/2 is
    // exact and does not change the direction, so it is skipped.
    err = 12.0 * kEps * abs_products;
    return n;
}

// A moving triangle's three control vectors n0, n2 and 2 n1 (below), with their error bounds.
inline void control_vectors(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1,
                            const Vec3& c1, Vec3 n[3], double err[3]) {
    const Vec3 e10 = b0 - a0, e20 = c0 - a0, e11 = b1 - a1, e21 = c1 - a1;
    const Vec3 u0[1] = {e10}, w0[1] = {e20};
    const Vec3 u2[1] = {e11}, w2[1] = {e21};
    const Vec3 u1[2] = {e10, e11}, w1[2] = {e21, e20};  // 2 n1 = e1(0) x e2(1) + e1(1) x e2(0)
    n[0] = control_vector(u0, w0, 1, err[0]);
    n[1] = control_vector(u2, w2, 1, err[1]);
    n[2] = control_vector(u1, w1, 2, err[2]);
}

// The triangle's CCD cone from the cones of its control vectors (in control_vectors' order).
inline NormalCone ccd_cone_of(const NormalCone c[3]) { return merge(merge(c[0], c[1]), c[2]); }

// Cone containing n(t) for all t in [0, 1] for the triangle moving from (a0, b0, c0) to (a1, b1, c1).
// Inline: out of line (another translation unit, so a call through the PLT in the module) the
// control vectors' cones took 65% of the CCD refit's samples with the merges (funnel, perf). The
// refit itself computes them in batches (LeafTriangles, bvh.cpp), bit for bit these.
inline NormalCone triangle_cone_ccd(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1,
                                    const Vec3& c1) {
    Vec3 n[3];
    double err[3];
    control_vectors(a0, b0, c0, a1, b1, c1, n, err);
    const NormalCone c[3] = {cone_around(n[0], err[0]), cone_around(n[1], err[1]), cone_around(n[2], err[2])};
    return ccd_cone_of(c);
}

}  // namespace conecull
