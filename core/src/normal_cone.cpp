#include "conecull/cone/normal_cone.hpp"

#include <algorithm>

#include "conecull/predicates/orient.hpp"

namespace conecull {

namespace {

// Absorbs every rounding in the cosine computations below. Each quantity there is in [-1, 1]
// and is computed with an absolute error of at most a few tens of kEps (~1e-15); normalised
// axes are unit up to 3 kEps, and a flushed component moves an axis by < 2^-59.
constexpr double kConeSlack = 1e-12;
// Axis components below this are set to 0 so that the exact predicates on (positions, axis)
// never underflow (coordinates are limited to [2^-128, 2^128] by the bindings).
constexpr double kFlushBelow = 0x1p-60;

Vec3 normalized_flushed(const Vec3& v, double len) {
    Vec3 u{v.x / len, v.y / len, v.z / len};
    if (std::fabs(u.x) < kFlushBelow) u.x = 0.0;
    if (std::fabs(u.y) < kFlushBelow) u.y = 0.0;
    if (std::fabs(u.z) < kFlushBelow) u.z = 0.0;
    return u;
}

// sin(theta) from cos(theta) = m in (0, 1]; (1 - m)(1 + m) keeps the relative error small
// near m = 1 where 1 - m*m would cancel.
double sin_from_cos(double m) { return std::sqrt(std::max(0.0, (1.0 - m) * (1.0 + m))); }

}  // namespace

NormalCone triangle_cone(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e1 = b - a, e2 = c - a;
    const double m1 = e1.y * e2.z, m2 = e1.z * e2.y;
    const double m3 = e1.z * e2.x, m4 = e1.x * e2.z;
    const double m5 = e1.x * e2.y, m6 = e1.y * e2.x;
    const Vec3 n{m1 - m2, m3 - m4, m5 - m6};
    // |fl(n_i) - n_i| <= (4 eps + O(eps^2)) (|m| + |m'|): two rounded differences, one rounded
    // product and one rounded subtraction per term. 9 eps leaves a factor > 2 for the
    // roundings of this bound and of r below.
    const double ex = 9.0 * kEps * (std::fabs(m1) + std::fabs(m2));
    const double ey = 9.0 * kEps * (std::fabs(m3) + std::fabs(m4));
    const double ez = 9.0 * kEps * (std::fabs(m5) + std::fabs(m6));
    const double err = std::sqrt(ex * ex + ey * ey + ez * ez);
    const double len = norm(n);
    const double r = err / len;  // sin of the largest angle between fl(n) and the exact n
    if (!(len > 0.0) || !(r < 0.5) || !std::isfinite(len)) return NormalCone::full();
    NormalCone cone;
    cone.axis = normalized_flushed(n, len);
    cone.cos_bound = sin_from_cos(r) - kConeSlack;  // cos(asin r) = sqrt(1 - r^2)
    return cone;
}

NormalCone merge(const NormalCone& p, const NormalCone& q) {
    if (!p.bounded() || !q.bounded()) return NormalCone::full();
    const Vec3 s = p.axis + q.axis;
    const double len = norm(s);
    // Nearly opposite axes: the merged cone is about a hemisphere or wider.
    if (!(len > 0.1)) return NormalCone::full();
    NormalCone out;
    out.axis = normalized_flushed(s, len);
    double bound = 1.0;
    for (const NormalCone* child : {&p, &q}) {
        // angle(n, axis) <= theta_child + phi with cos(theta_child) = cos_bound, phi the angle
        // between the axes; cos(theta + phi) = cos theta cos phi - sin theta sin phi.
        const double cos_phi = dot(out.axis, child->axis);
        const double sin_phi = norm(cross(out.axis, child->axis));
        const double m = child->cos_bound;
        bound = std::min(bound, m * cos_phi - sin_from_cos(m) * sin_phi);
    }
    // theta + phi < 3 pi / 2 here, so cos(theta + phi) <= 0 exactly when theta + phi >= pi / 2:
    // a non-positive bound is a full cone and never a false "bounded".
    out.cos_bound = bound - kConeSlack;
    if (!(out.cos_bound > 0.0)) return NormalCone::full();
    return out;
}

}  // namespace conecull
