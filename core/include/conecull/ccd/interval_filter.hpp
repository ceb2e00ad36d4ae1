// The certified time-axis test of exact-mode CCD (interval_filter.cpp): Bernstein enclosures
// of the coplanarity cubic and of sign conditions over pieces of [0, 1], in interval
// arithmetic. Its "apart" and "contact" are proofs; "unknown" goes to the exact decision.
#pragma once

#include "conecull/vec3.hpp"

namespace conecull {

enum class TimeAxisVerdict { kApart, kContact, kUnknown };

// Vertex p moving p0 -> p1 against the face (a, b, c); at most `budget` pieces are examined.
TimeAxisVerdict vertex_face_time_axis(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                                      const Vec3& a1, const Vec3& b1, const Vec3& c1, int budget);

// Edge (a, b) against edge (c, d).
TimeAxisVerdict edge_edge_time_axis(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                                    const Vec3& b1, const Vec3& c1, const Vec3& d1, int budget);

// The enclosures on [0, 1] the two tests above start from, for the exact-twin tests: the Bernstein
// coefficients of f (4), then of each condition (5 each; VF: 9, h[3 i + k] = o_i,k n_k; EE: 6,
// h[2 k] = -(T1 T2)_k, h[2 k + 1] = -(T3 T4)_k), lower ends in lo and upper ends in hi (4 + 5 * 9
// or 4 + 5 * 6 each). x: the eight points in the argument order of the test.
void time_axis_enclosures(bool vertex_face, const Vec3 (&x)[8], double* lo, double* hi);

// Vertex q against the segment [x, y], when q, x and y share one coordinate exactly at t = 0
// and t = 1 (they then move in an axis-aligned plane, as on the symmetry planes of meshed
// scenes): kContact when the time-axis test proves q crosses the segment's interior (a
// contact of every pair holding that vertex and that segment, at the pair's domain boundary,
// where Miranda's box cannot fit), else kUnknown.
TimeAxisVerdict vertex_segment_planar_contact(const Vec3& q0, const Vec3& x0, const Vec3& y0, const Vec3& q1,
                                              const Vec3& x1, const Vec3& y1, int budget);

}  // namespace conecull
