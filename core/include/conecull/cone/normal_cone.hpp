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

#include <cmath>

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

// Cone of one triangle: around its rounded normal, widened by the rounding error bound of
// the cross product; a triangle whose normal is not resolved (zero or tiny area) is full.
NormalCone triangle_cone(const Vec3& a, const Vec3& b, const Vec3& c);

// Bottom-up merge (Sec. 3.6 "merge these bounds in a bottom-up manner"): a cone around the
// bisector of both axes containing both cones, by the spherical triangle inequality.
NormalCone merge(const NormalCone& p, const NormalCone& q);

}  // namespace conecull
