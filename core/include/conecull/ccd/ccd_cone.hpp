// Normal cones for CCD (Sec. 3.6): with every vertex moving linearly over t in [0, 1], a
// triangle's normal n(t) = e1(t) x e2(t) is quadratic in t. In Bernstein form
//     n(t) = (1-t)^2 n0 + 2t(1-t) n1 + t^2 n2,
//     n0 = e1(0) x e2(0),  n2 = e1(1) x e2(1),  n1 = (e1(0) x e2(1) + e1(1) x e2(0)) / 2,
// a non-negative combination of the three control normals, so a cone (half-angle < pi/2)
// holding all three holds n(t) for every t. Each control normal is widened by a rigorous
// bound on its rounding error, exactly as for DCD; a zero or unresolved one gives a full cone.
#pragma once

#include "conecull/cone/normal_cone.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

// Cone of one control vector given as the sum of cross products sum_k (u_k x w_k) * scale,
// with u_k, w_k rounded differences (their error is accounted for like triangle_cone's).
NormalCone control_vector_cone(const Vec3* u, const Vec3* w, int terms);

// Cone containing n(t) for all t in [0, 1] for the triangle moving from (a0, b0, c0) to (a1, b1, c1).
NormalCone triangle_cone_ccd(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1,
                             const Vec3& c1);

}  // namespace conecull
