// Normal cones (Sec. 3.2, Fig. 2), conservative under floating point.
//
// Invariant, for the exact double vector `axis` the contour test later uses as l: there is a
// half-angle theta in [0, pi/2) with cos(theta) >= cos_bound and sin(theta) <= sin_bound such
// that every triangle T below the node has an exact normal n_T = (b - a) x (c - a) (computed
// from the double coordinates, not the rounded cross product) within theta of axis; hence
//        n_T . axis >= cos_bound * |n_T| * |axis|.
// So cos_bound > 0 (apex angle < pi, Alg. 2 line 5) proves n_T . axis > 0 for every T.
// Kept as a cosine/sine pair rather than an angle: merging then needs two square roots and no
// trig, and every rounding stays a small absolute error that kConeSlack absorbs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "conecull/predicates/orient.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

struct NormalCone {
    Vec3 axis;               // l, unit length up to rounding; tiny components flushed to 0
    double cos_bound = -1;   // lower bound on cos(theta); <= 0: full cone
    double sin_bound = 1;    // upper bound on sin(theta)

    bool bounded() const { return cos_bound > 0.0; }  // ApexAngle(C_N) < pi
    // Apex angle (Fig. 2's alpha = twice the half-angle), for reporting only.
    double apex_angle() const {
        return cos_bound > 0.0 ? 2.0 * std::acos(cos_bound < 1.0 ? cos_bound : 1.0) : 2.0 * M_PI;
    }
    static NormalCone full() { return {}; }
};
static_assert(sizeof(NormalCone) == 40, "NormalCone: axis (24 B) + cos_bound + sin_bound (16 B)");

// Absorbs every rounding in the cosine computations below. Each quantity there is in [-1, 1]
// and is computed with an absolute error of at most a few tens of kEps (~1e-15); normalised
// axes are unit up to 5 kEps, and a flushed component moves an axis by < 2^-59.
inline constexpr double kConeSlack = 1e-12;
// Axis components below this are set to 0 so that the exact predicates on (positions, axis)
// never underflow (coordinates are limited to [2^-128, 2^128] by the bindings).
inline constexpr double kFlushBelow = 0x1p-60;

// v / |v| with tiny components flushed to 0, given inv_len = 1 / |v| (one division per cone:
// a product by the rounded reciprocal is within 2 eps + eps^2 of the quotient).
inline Vec3 unit_axis(const Vec3& v, double inv_len) {
    Vec3 u{v.x * inv_len, v.y * inv_len, v.z * inv_len};
    if (std::fabs(u.x) < kFlushBelow) u.x = 0.0;
    if (std::fabs(u.y) < kFlushBelow) u.y = 0.0;
    if (std::fabs(u.z) < kFlushBelow) u.z = 0.0;
    return u;
}

// The cone around a rounded vector n whose exact value is within err (L2) of it: full if n is
// not resolved (zero, not finite, or err >= |n| / 2).
inline NormalCone cone_around(const Vec3& n, double err) {
    const double len = norm(n);
    const double inv_len = 1.0 / len;
    // sin of the largest angle between fl(n) and the exact n: angle <= asin(r).
    const double r = err * inv_len;
    if (!(len > 0.0) || !(r < 0.5) || !std::isfinite(len)) return NormalCone::full();
    NormalCone cone;
    cone.axis = unit_axis(n, inv_len);
    // theta = asin(r) + (normalisation and flush, < 1e-15): cos(theta) >= 1 - r - slack since
    // sqrt(1 - r^2) >= 1 - r, and sin(theta) <= r + slack.
    cone.cos_bound = 1.0 - r - kConeSlack;
    cone.sin_bound = r + kConeSlack;
    return cone;
}

// fl(u x w), each component the rounded difference of two rounded products m - m'; adds the sum
// of the six |m| to abs_products (the scale of its rounding error).
inline Vec3 rounded_cross(const Vec3& u, const Vec3& w, double& abs_products) {
    const double m1 = u.y * w.z, m2 = u.z * w.y;
    const double m3 = u.z * w.x, m4 = u.x * w.z;
    const double m5 = u.x * w.y, m6 = u.y * w.x;
    abs_products += std::fabs(m1) + std::fabs(m2) + std::fabs(m3) + std::fabs(m4) + std::fabs(m5) + std::fabs(m6);
    return {m1 - m2, m3 - m4, m5 - m6};
}

// A triangle's rounded normal n = fl((b - a) x (c - a)) and the bound err on its rounding error:
// |fl(n_i) - n_i| <= (4 eps + O(eps^2)) (|m| + |m'|), two rounded differences, one rounded product
// and one rounded subtraction per term. 9 eps leaves a factor > 2 for the roundings of this bound
// and of r in cone_around; the L1 norm bounds the L2 norm of the error.
inline Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c, double& err) {
    double abs_products = 0.0;
    const Vec3 n = rounded_cross(b - a, c - a, abs_products);
    err = 9.0 * kEps * abs_products;
    return n;
}

// Cone of one triangle: around its rounded normal, widened by the rounding error bound of
// the cross product; a triangle whose normal is not resolved (zero or tiny area) is full.
// Inline, as merge, and one division per cone rather than four: together about 30% off the
// refit with cones (measured).
inline NormalCone triangle_cone(const Vec3& a, const Vec3& b, const Vec3& c) {
    double err;
    const Vec3 n = triangle_normal(a, b, c, err);
    return cone_around(n, err);
}

// cone_around for `count` normals given as columns (x, y, z, err), into out[0, count): the same
// operations in the same order, so bit for bit the same cones, two at a time in SSE2 (part of
// x86-64, so no dispatch). Why: the refit's square root and division per triangle are
// independent from one triangle to the next, and batched they overlap instead of waiting on each
// other inside the sweep (leaf cones were a third of the DCD refit).
inline void cones_around(const double* x, const double* y, const double* z, const double* err, int32_t count,
                         NormalCone* out) {
    int32_t i = 0;
#if defined(__SSE2__)
    const __m128d zero = _mm_setzero_pd(), half = _mm_set1_pd(0.5), one = _mm_set1_pd(1.0);
    const __m128d largest = _mm_set1_pd(std::numeric_limits<double>::max());
    const __m128d slack = _mm_set1_pd(kConeSlack), flush = _mm_set1_pd(kFlushBelow), sign = _mm_set1_pd(-0.0);
    const __m128d full_cos = _mm_set1_pd(NormalCone::full().cos_bound), full_sin = _mm_set1_pd(NormalCone::full().sin_bound);
    for (; i + 2 <= count; i += 2) {
        const __m128d nx = _mm_loadu_pd(x + i), ny = _mm_loadu_pd(y + i), nz = _mm_loadu_pd(z + i);
        // len = norm(n), inv_len = 1 / len, r = err inv_len (cone_around).
        const __m128d len =
            _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(nx, nx), _mm_mul_pd(ny, ny)), _mm_mul_pd(nz, nz)));
        const __m128d inv = _mm_div_pd(one, len);
        const __m128d r = _mm_mul_pd(_mm_loadu_pd(err + i), inv);
        // Resolved: len > 0, r < 0.5 and len finite (ordered compares: false on NaN, as there).
        const __m128d ok =
            _mm_and_pd(_mm_and_pd(_mm_cmpgt_pd(len, zero), _mm_cmplt_pd(r, half)), _mm_cmple_pd(len, largest));
        // unit_axis: the component times inv_len, 0 if below kFlushBelow in magnitude; 0 (the full
        // cone's axis) where not resolved.
        const auto unit = [&](__m128d v) {
            const __m128d u = _mm_mul_pd(v, inv);
            return _mm_and_pd(ok, _mm_andnot_pd(_mm_cmplt_pd(_mm_andnot_pd(sign, u), flush), u));
        };
        const __m128d ux = unit(nx), uy = unit(ny), uz = unit(nz);
        const __m128d cb = _mm_or_pd(_mm_and_pd(ok, _mm_sub_pd(_mm_sub_pd(one, r), slack)), _mm_andnot_pd(ok, full_cos));
        const __m128d sb = _mm_or_pd(_mm_and_pd(ok, _mm_add_pd(r, slack)), _mm_andnot_pd(ok, full_sin));
        NormalCone& c0 = out[i];
        NormalCone& c1 = out[i + 1];
        _mm_storel_pd(&c0.axis.x, ux), _mm_storeh_pd(&c1.axis.x, ux);
        _mm_storel_pd(&c0.axis.y, uy), _mm_storeh_pd(&c1.axis.y, uy);
        _mm_storel_pd(&c0.axis.z, uz), _mm_storeh_pd(&c1.axis.z, uz);
        _mm_storel_pd(&c0.cos_bound, cb), _mm_storeh_pd(&c1.cos_bound, cb);
        _mm_storel_pd(&c0.sin_bound, sb), _mm_storeh_pd(&c1.sin_bound, sb);
    }
#endif
    for (; i < count; ++i) out[i] = cone_around({x[i], y[i], z[i]}, err[i]);
}

// The cone around an axis a (unit up to rounding) holding the cones p and q, or full, given
// cos and sin of the angles phi_p, phi_q from a to their axes (each within a few eps). Every
// normal below lies within psi_i = phi_i + theta_i of a (theta_i a child's half-angle); while
// psi_i < pi/2,
// cos(psi_i) = cos(theta_i) cos(phi_i) - sin(theta_i) sin(phi_i) >= cos_bound cos(phi_i) - sin_bound sin(phi_i),
// sin(psi_i) = sin(theta_i) cos(phi_i) + cos(theta_i) sin(phi_i) <= sin_bound cos(phi_i) + sin(phi_i),
// with every rounding inside kConeSlack. psi_i < 3 pi / 2, so a positive lower bound on
// cos(psi_i) proves psi_i < pi/2: a non-positive bound is a full cone, never a false "bounded".
inline NormalCone cone_about(const Vec3& a, const NormalCone& p, double cp, double sp, const NormalCone& q, double cq,
                             double sq) {
    NormalCone out;
    out.axis = a;
    out.cos_bound = std::min(p.cos_bound * cp - p.sin_bound * sp, q.cos_bound * cq - q.sin_bound * sq) - kConeSlack;
    out.sin_bound = std::max(p.sin_bound * cp + sp, q.sin_bound * cq + sq) + kConeSlack;
    if (!(out.cos_bound > 0.0)) return NormalCone::full();
    return out;
}

// A cone holding p and q around the bisector of their axes, by the spherical triangle
// inequality: at angle phi from both axes, its half-angle is phi + max(theta_p, theta_q).
inline NormalCone merge_bisector(const NormalCone& p, const NormalCone& q) {
    const Vec3 s = p.axis + q.axis;
    const double len = norm(s);
    // Nearly opposite axes: the merged cone is about a hemisphere or wider.
    if (!(len > 0.1)) return NormalCone::full();
    // |p + q| = 2 cos(phi), |p - q| = 2 sin(phi).
    const double cos_phi = 0.5 * len, sin_phi = 0.5 * norm(p.axis - q.axis);
    return cone_about(unit_axis(s, 1.0 / len), p, cos_phi, sin_phi, q, cos_phi, sin_phi);
}

// Below this cosine the merge looks for the smallest cone (about 26 degrees of half-angle):
// narrower bisector cones are kept as they are. Measured on the scenes: the same culling as the
// smallest cone everywhere (elementary tests within 0.5%), for 10% more instructions in the
// refit instead of 55% (funnel, callgrind).
inline constexpr double kMergeNarrow = 0.9;

// The narrower of two valid cones.
inline NormalCone best(const NormalCone& a, const NormalCone& b) { return b.cos_bound > a.cos_bound ? b : a; }

// merge beyond kMergeNarrow: the axis of the smallest cone (see merge), given the bisector's
// cone b. Out of line, so that the refit's loop stays small: inlined, it made the refit with two
// threads as slow as with one (measured: 2.3-3.4 ms against 2.2 ms on the 64K fold; out of
// line, 1.1 ms).
[[gnu::noinline]] inline NormalCone merge_wide(const NormalCone& p, const NormalCone& q, const NormalCone& b) {
    const double cphi = dot(p.axis, q.axis), sphi = norm(cross(p.axis, q.axis));
    // z = e^{i 2 alpha} = e^{i phi} e^{i theta_q} e^{-i theta_p}; the bound pairs stand in for
    // (cos, sin) of the half-angles (unit up to kConeSlack and the triangles' tiny r). Then
    // 1 + z = 2 cos(alpha) e^{i alpha}: (ca, sa) = (1 + Re z, Im z) is (cos, sin) of alpha scaled
    // by 2 cos(alpha) > 0 (alpha < pi/2 wherever the merged cone is bounded), no square root.
    const double ur = cphi * q.cos_bound - sphi * q.sin_bound, ui = cphi * q.sin_bound + sphi * q.cos_bound;
    const double ca = 1.0 + (ur * p.cos_bound + ui * p.sin_bound), sa = ui * p.cos_bound - ur * p.sin_bound;
    if (!(ca > 0.0)) return b;  // alpha near pi/2: about a hemisphere anyway
    if (!(sa > 0.0)) return best(b, cone_about(p.axis, p, dot(p.axis, p.axis), 0.0, q, cphi, sphi));  // p holds q
    // v = cos(alpha) p + sin(alpha) (q - cos(phi) p) / sin(phi), times sin(phi) (> 0 here):
    // v = wp p + wq q. Then |v x p| = wq sin(phi) and |v x q| = |wp| sin(phi).
    const double wq = sa, wp = ca * sphi - sa * cphi;
    if (!(wp > 0.0)) return best(b, cone_about(q.axis, p, cphi, sphi, q, dot(q.axis, q.axis), 0.0));  // q holds p
    const Vec3 v{wp * p.axis.x + wq * q.axis.x, wp * p.axis.y + wq * q.axis.y, wp * p.axis.z + wq * q.axis.z};
    const double len = norm(v);
    if (!(len > 0.0) || !std::isfinite(len)) return b;
    const double inv = 1.0 / len;
    const Vec3 a = unit_axis(v, inv);
    // The sines from a itself, like the cosines: wq sin(phi) / |v| is the same value in exact
    // arithmetic, but for nearly opposite axes v nearly cancels, |v| carries a relative error of
    // ~eps / (pi - phi), and that sine could fall short of the true one by far more than
    // kConeSlack (found by review: 8e-9 for two narrow antipodal cones).
    return best(b, cone_about(a, p, dot(a, p.axis), norm(cross(a, p.axis)), q, dot(a, q.axis), norm(cross(a, q.axis))));
}

// A bounded cone's half-angle is in [0, pi/2), so sin(theta) <= sqrt(1 - cos_bound^2) as well.
// Without this, sin_bound (each merge bounds sin(phi + theta) by sin_bound cos(phi) + sin(phi),
// taking cos(theta) <= 1) drifts up level by level: above 1.2 on falling's nodes, whose merged
// cones then came out full although their children's cones fit within 82-89 degrees of an
// axis. 1 - cb^2 is computed within 2 kEps of its value; adding 4 kEps before the root and
// kConeSlack after it keeps the computed cap above the exact one. (Were cb rounded above 1, the
// root would be NaN and std::min keep sin_bound.)
inline NormalCone with_sin_from_cos(NormalCone c) {
    if (c.bounded()) c.sin_bound = std::min(c.sin_bound, std::sqrt(1.0 - c.cos_bound * c.cos_bound + 4.0 * kEps) + kConeSlack);
    return c;
}

// Bottom-up merge (Sec. 3.6 "merge these bounds in a bottom-up manner"): the smallest cone
// holding both, up to rounding. Its axis lies on the great circle through both axes (phi
// apart), turned from p's towards q's by alpha = (phi + theta_q - theta_p) / 2, clamped to
// [0, phi] (then one cone holds the other), and its half-angle is (phi + theta_p + theta_q) / 2.
// The bisector of the axes (alpha = phi / 2) is that only for equally wide cones; otherwise its
// half-angle exceeds it by |theta_p - theta_q| / 2, and the excess adds up level by level: on the
// funnel scene, 1622 of the 2735 full bisector cones among the nodes the traversal visits become
// bounded. Trig-free: angles are (cos, sin) pairs, e^{i 2 alpha} = e^{i phi} e^{i theta_q}
// e^{-i theta_p} and alpha from 1 + e^{i 2 alpha}. Choosing the axis needs no rigour (any
// axis is valid); cone_about then bounds the cone around it.
inline NormalCone merge(const NormalCone& p, const NormalCone& q) {
    if (!p.bounded() || !q.bounded()) return NormalCone::full();
    const NormalCone b = merge_bisector(p, q);
    return with_sin_from_cos(b.cos_bound > kMergeNarrow ? b : merge_wide(p, q, b));
}

}  // namespace conecull
