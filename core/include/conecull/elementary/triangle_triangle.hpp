// Exact triangle-triangle test for DCD (Sec. 5.1: "triangle-triangle intersection tests for
// DCD"), with the pair semantics of conecull: closed triangles (possibly degenerate) collide
// iff their intersection is not contained in the convex hull S of the positions of the
// vertices they share. No shared vertex: they touch anywhere. One shared vertex v: they meet
// somewhere other than v. A shared edge: they meet off that edge. Same three vertices: never.
//
// Decision procedure (proof sketch): P = T1 n T2 is convex and contains S. P is not inside S
// iff an extreme point of P lies outside S, and every extreme point of P lies on an edge of
// one triangle and in the other (degenerate triangles are covered by their edges). So
// "collide" iff some edge e of one triangle has (e n other) not inside S. Only exact sign
// predicates are used: orient3d, orient2d on coordinate planes, and coordinate comparisons.
#pragma once

#include <cstdint>

#include "conecull/vec3.hpp"

namespace conecull {

// Closed segment [p, q] meets closed triangle (a, b, c); either may be degenerate.
bool segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);
// The same when p and q are known to lie on opposite sides of the proper triangle's plane, or
// one of them on it (the other not): only the line pq against the three edges remains.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);
// Closed segments [p, q] and [a, b] meet; either may be a point.
bool segment_meets_segment(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b);
// x lies on the closed segment [p, q].
bool point_on_segment(const Vec3& x, const Vec3& p, const Vec3& q);
// a, b, c collinear (or coincident).
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c);

// The full test; fp, fq are the faces' vertex ids (they decide what is shared), P, Q their
// positions in the same order.
bool triangles_collide(const int32_t fp[3], const Vec3 P[3], const int32_t fq[3], const Vec3 Q[3]);

}  // namespace conecull
