// Elementary CCD tests (Sec. 5.1: "exact elementary tests for CCD"): vertex-face and
// edge-edge, closed primitives, every vertex moving linearly over t in [0, 1]; contact at any
// t, t = 0 and t = 1 included.
//
// Arithmetic modes:
//   kFloat         plain double root finding on the coplanarity cubic with the usual epsilons
//                  (fast; may miss or invent contacts);
//   kConservative  inclusion-based: F(t, u, v) = 0 is searched over the parameter box by
//                  subdivision; each component of F is multilinear in (t, u, v), so its range on
//                  a box lies between its corner values, which are evaluated with a rigorous
//                  rounding-error bound. A box is dropped only when some component provably
//                  keeps one sign on it, so no contact is ever missed; boxes that stay
//                  undecided down to the tolerance (or past the box budget) report contact.
//   kExact         a shallow conservative test (its "no" is final), exact static contact at
//                  t = 0 or 1, a certified time-axis test (Bernstein enclosures in interval
//                  arithmetic: proves near misses apart and contacts, incl. a vertex crossing
//                  an edge in an axis-aligned plane), contacts proven by Miranda's theorem,
//                  then an exact decision: exact root isolation of the polynomials in t with dyadic
//                  arithmetic and their signs at those roots (exact_ccd.cpp) - exactly the
//                  answer for the given doubles.
// Every mode first orders the corners by their coordinates, so an answer (and a time-of-impact
// bound) depends on the moving points only, never on the order they are passed in.
#pragma once

#include <cstdint>

#include "conecull/vec3.hpp"

namespace conecull {

enum class Arithmetic { kFloat, kConservative, kExact };

struct CcdOptions {
    int max_depth = 24;          // boxes 2^-24 wide in every parameter that stay undecided: "contact"
    int max_boxes = 20000;       // budget per query; exceeded -> "contact" (conservative)
};

// How exact-mode decisions were reached (per thread; the collider resets and reports them).
struct ExactPathCounts {
    int64_t filtered = 0;        // excluded by the shallow conservative filter
    int64_t static_contact = 0;  // contact at t = 0 or t = 1 (exact static predicates)
    int64_t proven_contact = 0;  // contact proven by the time-axis test or Miranda's theorem
    int64_t interval_filtered = 0;   // excluded by the certified time-axis (interval) test
    int64_t exact_engine = 0;    // decided by exact root isolation
};
ExactPathCounts& exact_path_counts();

// Vertex p moving p0 -> p1 against the face (a, b, c) moving (a0, b0, c0) -> (a1, b1, c1).
bool vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1, const Vec3& a1,
                     const Vec3& b1, const Vec3& c1, Arithmetic mode, const CcdOptions& opt = {});

// Edge (a, b) against edge (c, d), each end moving linearly.
bool edge_edge_ccd(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1, const Vec3& b1,
                   const Vec3& c1, const Vec3& d1, Arithmetic mode, const CcdOptions& opt = {});

// For a pair in contact: a lower bound on its earliest contact time: the inclusion search,
// visiting boxes in order of their start time, stops at the first one it cannot exclude once
// 2^-20 wide in t, u and v (or when its budget runs out); every box starting earlier was
// excluded, so no contact happens before that box's start.
double vertex_face_toi_lower_bound(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                                   const Vec3& a1, const Vec3& b1, const Vec3& c1);
double edge_edge_toi_lower_bound(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                                 const Vec3& b1, const Vec3& c1, const Vec3& d1);

}  // namespace conecull
