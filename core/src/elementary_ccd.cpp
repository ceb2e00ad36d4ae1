#include "conecull/ccd/elementary_ccd.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "conecull/ccd/interval_filter.hpp"
#include "conecull/elementary/triangle_triangle.hpp"
#include "conecull/predicates/orient.hpp"

namespace conecull {

namespace {

// ---- conservative: inclusion by subdivision -------------------------------------------------

// F(t, u, v) = P(t) + u U(t) + v W(t) with P, U, W linear in t; per component multilinear.
// VF: P = p - a, U = -(b - a), W = -(c - a).   EE: P = a - c, U = b - a, W = -(d - c).
struct MovingTerms {
    Vec3 P0, P1, U0, U1, W0, W1;  // values at t = 0 and t = 1 (rounded differences)
    double scale;                 // bound on |everything| for the rounding error term
};

struct Box {
    double t0, t1, u0, u1, v0, v1;
    int depth;
};

// Value of F at a corner and a bound on its rounding error. Entries of MovingTerms are rounded
// differences of inputs (relative error eps, accounted for in `scale` with factor 2); the
// evaluation is a handful of products and sums of terms bounded by `scale`.
inline Vec3 corner_value(const MovingTerms& m, double t, double u, double v) {
    const Vec3 P = m.P0 + t * (m.P1 - m.P0);
    const Vec3 U = m.U0 + t * (m.U1 - m.U0);
    const Vec3 W = m.W0 + t * (m.W1 - m.W0);
    return P + u * U + v * W;
}

// The pending boxes of inclusion_search: a heap ordered by t0 when the first contact time is
// wanted, else a depth-first stack. Depth-first, a split replaces a box by its two halves and
// the depth is capped at 3 max_depth, so at most 3 max_depth + 2 boxes are ever pending: they
// fit in an array on the stack. The exact mode runs this search as a filter on every pair it
// tests, and a std::vector there cost an allocation and a reallocation or two per pair.
class BoxStack {
   public:
    static constexpr int kMaxDepth = 64;  // CcdOptions::max_depth above this: a std::logic_error
    explicit BoxStack(bool ordered) : ordered_(ordered) {}
    bool empty() const { return ordered_ ? heap_.empty() : size_ == 0; }
    void push(const Box& b) {
        if (!ordered_) {
            fixed_[size_++] = b;
            return;
        }
        heap_.push_back(b);
        std::push_heap(heap_.begin(), heap_.end(), later);
    }
    Box pop() {
        if (!ordered_) return fixed_[--size_];
        std::pop_heap(heap_.begin(), heap_.end(), later);
        const Box b = heap_.back();
        heap_.pop_back();
        return b;
    }

   private:
    static bool later(const Box& p, const Box& q) { return p.t0 > q.t0 || (p.t0 == q.t0 && p.depth < q.depth); }
    bool ordered_;
    int size_ = 0;
    Box fixed_[3 * kMaxDepth + 2];  // uninitialised until pushed
    std::vector<Box> heap_;         // allocates only when ordered
};

bool inclusion_search(const MovingTerms& m, bool triangle_domain, const CcdOptions& opt, double* first_t = nullptr) {
    if (opt.max_depth > BoxStack::kMaxDepth) throw std::logic_error("inclusion_search: max_depth above 64");
    // |P|, |U|, |W| <= scale at t = 0, 1, so every intermediate is below 9 scale (|t|, |u|,
    // |v| <= 1). In absolute terms every rounding of the evaluation adds its own error, not only
    // those on the longest chain: 13 roundings (three each for P, U and W, the two products and
    // the two sums), each at most eps * 9 scale, and the rounded input differences (relative
    // error eps) carry at most 9 eps scale through the multilinear form: < 130 eps scale in all
    // (a finer count gives 25); 256 eps scale is the bound used.
    const double err = 256.0 * kEps * m.scale;
    // Depth-first for a yes/no answer; ordered by t0 when the first contact time is wanted
    // (then every box with a smaller t0 has been excluded when one is reported).
    BoxStack stack(first_t != nullptr);
    stack.push({0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0});
    const Vec3 dP = m.P1 - m.P0, dU = m.U1 - m.U0, dW = m.W1 - m.W0;
    int boxes = 0;
    const double tol = std::ldexp(1.0, -opt.max_depth);  // a box this wide in every parameter is undecided
    while (!stack.empty()) {
        const Box b = stack.pop();
        ++boxes;
        if (triangle_domain && b.u0 + b.v0 > 1.0) continue;  // dyadic sums: exact
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        // F at the corners, corner c: t from bit 0, u from bit 1, v from bit 2. P, U and W at
        // each end of the box's t-range once (the values corner_value would round, bit for bit).
        const Vec3 P[2] = {m.P0 + b.t0 * dP, m.P0 + b.t1 * dP};
        const Vec3 U[2] = {m.U0 + b.t0 * dU, m.U0 + b.t1 * dU};
        const Vec3 W[2] = {m.W0 + b.t0 * dW, m.W0 + b.t1 * dW};
        Vec3 f[8];
        for (int c = 0; c < 8; ++c) {
            const int e = c & 1;
            f[c] = P[e] + (c & 2 ? b.u1 : b.u0) * U[e] + (c & 4 ? b.v1 : b.v0) * W[e];
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], f[c][k]);
                hi[k] = std::max(hi[k], f[c][k]);
            }
        }
        bool excluded = false;
        for (int k = 0; k < 3; ++k) excluded |= lo[k] - err > 0.0 || hi[k] + err < 0.0;
        if (excluded) continue;
        // Split, among the parameters still wider than the tolerance 2^-max_depth, the one along
        // which F changes most. Why not round robin: where contact is possible only near one end
        // of the step (everything meeting at t = 1), it refined u and v as often as t, and the
        // boxes grew 4x per halving of t until the budget ran out (README, "Conservative mode's
        // splitting"). The change along a parameter is measured on the box's edge from its first
        // corner in that direction; a toi bound, whose quality depends on splitting t wherever
        // F moves with t, takes the largest over all four parallel edges (one edge can show no
        // change in t while the others do: the bound then stayed at t0 = 0); the yes/no search
        // keeps one edge, which measured 10-20% faster on the real steps (app/BENCHMARKS.md).
        const double width[3] = {b.t1 - b.t0, b.u1 - b.u0, b.v1 - b.v0};
        int axis = -1;
        double most = -1.0;
        for (int a = 0; a < 3; ++a) {
            if (!(width[a] > tol)) continue;
            const int bit = 1 << a;
            double change = 0.0;
            for (int c = 0; c < (first_t ? 8 : 1); ++c) {
                if (c & bit) continue;
                for (int k = 0; k < 3; ++k) change = std::max(change, std::fabs(f[c | bit][k] - f[c][k]));
            }
            if (change > most) most = change, axis = a;
        }
        // Undecided at the tolerance: contact. (The depth cap only backs up the widths: a
        // max_depth beyond the doubles' resolution could not narrow a box further.)
        if (axis < 0 || b.depth >= 3 * opt.max_depth || boxes >= opt.max_boxes) {
            if (first_t) *first_t = b.t0;  // the smallest t0 of all boxes left: no contact before it
            return true;
        }
        Box l = b, r = b;
        l.depth = r.depth = b.depth + 1;
        if (axis == 0) l.t1 = r.t0 = 0.5 * (b.t0 + b.t1);
        if (axis == 1) l.u1 = r.u0 = 0.5 * (b.u0 + b.u1);
        if (axis == 2) l.v1 = r.v0 = 0.5 * (b.v0 + b.v1);
        stack.push(r);
        stack.push(l);  // depth-first: the earlier (or lower) half first
    }
    return false;
}

double max_abs(std::initializer_list<Vec3> vs) {
    double s = 0.0;
    for (const Vec3& v : vs) s = std::max({s, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    return s;
}

// ---- certified contact: Miranda's theorem on a small box around an approximate root --------
//
// G = M F with M an approximate inverse of the Jacobian of F at an approximate root. If, on a
// box B inside the domain, each G_k is <= 0 on the face x_k = low and >= 0 on the face
// x_k = high (or the reverse), G has a zero in B (Miranda), and so does F when M is
// invertible: a contact, proven with floating point only. G_k is multilinear like F, so its
// range on a face lies between the face's corner values; every value carries a rigorous error
// bound. Failing to prove is never an answer: the caller falls back to the exact decision.
bool miranda_contact(const MovingTerms& m, bool triangle_domain, double t, double u, double v) {
    // Jacobian of F(t, u, v) = P(t) + u U(t) + v W(t) at the estimate.
    const Vec3 dP = m.P1 - m.P0, dU = m.U1 - m.U0, dW = m.W1 - m.W0;
    const Vec3 Ft = dP + u * dU + v * dW, Fu = m.U0 + t * dU, Fv = m.W0 + t * dW;
    // M = J^-1 with J = [Ft Fu Fv] (columns): rows of M are cross products / det.
    const Vec3 r0 = cross(Fu, Fv), r1 = cross(Fv, Ft), r2 = cross(Ft, Fu);
    const double det = dot(Ft, r0);
    if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) return false;
    const Vec3 M[3] = {(1.0 / det) * r0, (1.0 / det) * r1, (1.0 / det) * r2};
    // M must be invertible: its determinant, with a rigorous bound, must be non-zero.
    {
        const double m1 = M[1].y * M[2].z, m2 = M[1].z * M[2].y, m3 = M[1].z * M[2].x, m4 = M[1].x * M[2].z,
                     m5 = M[1].x * M[2].y, m6 = M[1].y * M[2].x;
        const double dm = M[0].x * (m1 - m2) + M[0].y * (m3 - m4) + M[0].z * (m5 - m6);
        const double pm = std::fabs(M[0].x) * (std::fabs(m1) + std::fabs(m2)) + std::fabs(M[0].y) * (std::fabs(m3) + std::fabs(m4)) +
                          std::fabs(M[0].z) * (std::fabs(m5) + std::fabs(m6));
        if (!(std::fabs(dm) > 16.0 * kEps * pm)) return false;
    }
    // Box radius: at most 1e-6, and small enough to keep the box inside the domain.
    double rad = std::min({1e-6, 0.5 * t, 0.5 * (1.0 - t), 0.5 * u, 0.5 * v,
                           triangle_domain ? 0.25 * (1.0 - u - v) : 0.5 * (1.0 - u), triangle_domain ? 1.0 : 0.5 * (1.0 - v)});
    if (!(rad > 1e-11)) return false;
    const double lo[3] = {t - rad, u - rad, v - rad}, hi[3] = {t + rad, u + rad, v + rad};
    for (int k = 0; k < 3; ++k)
        if (lo[k] < 0.0 || hi[k] > 1.0) return false;
    if (triangle_domain && !(hi[1] + hi[2] <= 1.0 - 1e-12)) return false;
    const double errF = 256.0 * kEps * m.scale;
    const double rowsum[3] = {std::fabs(M[0].x) + std::fabs(M[0].y) + std::fabs(M[0].z),
                              std::fabs(M[1].x) + std::fabs(M[1].y) + std::fabs(M[1].z),
                              std::fabs(M[2].x) + std::fabs(M[2].y) + std::fabs(M[2].z)};
    // G_k at a point, with its error: |M_k . (F_exact - F_computed)| <= rowsum errF, plus the
    // roundings of the dot product (3 products, 2 sums) below 4 eps sum |M_kj F_j|.
    auto G_bounds = [&](int k, double tt, double uu, double vv, double& g, double& e) {
        const Vec3 f = corner_value(m, tt, uu, vv);
        g = dot(M[k], f);
        e = rowsum[k] * errF + 4.0 * kEps * (std::fabs(M[k].x * f.x) + std::fabs(M[k].y * f.y) + std::fabs(M[k].z * f.z));
        e *= 1.0 + 1e-10;
    };
    for (int k = 0; k < 3; ++k) {
        int face_sign[2] = {0, 0};
        for (int side = 0; side < 2; ++side) {
            double mn = INFINITY, mx = -INFINITY;
            for (int c = 0; c < 4; ++c) {  // the 4 corners of the face x_k = lo / hi
                double x[3];
                x[k] = side ? hi[k] : lo[k];
                x[(k + 1) % 3] = c & 1 ? hi[(k + 1) % 3] : lo[(k + 1) % 3];
                x[(k + 2) % 3] = c & 2 ? hi[(k + 2) % 3] : lo[(k + 2) % 3];
                double g, e;
                G_bounds(k, x[0], x[1], x[2], g, e);
                mn = std::min(mn, g - e);
                mx = std::max(mx, g + e);
            }
            face_sign[side] = mn > 0.0 ? 1 : (mx < 0.0 ? -1 : 0);
        }
        if (face_sign[0] == 0 || face_sign[1] == 0 || face_sign[0] == face_sign[1]) return false;
    }
    return true;
}

// ---- float: roots of the coplanarity cubic, then a proximity check with epsilons ------------

// Coefficients (c0 + c1 t + c2 t^2 + c3 t^3) of det[x(t), y(t), z(t)] with x(t) = x0 + t dx...
std::array<double, 4> cubic_of(const Vec3& x0, const Vec3& dx, const Vec3& y0, const Vec3& dy, const Vec3& z0,
                               const Vec3& dz) {
    auto det = [](const Vec3& a, const Vec3& b, const Vec3& c) { return dot(a, cross(b, c)); };
    return {det(x0, y0, z0), det(dx, y0, z0) + det(x0, dy, z0) + det(x0, y0, dz),
            det(dx, dy, z0) + det(dx, y0, dz) + det(x0, dy, dz), det(dx, dy, dz)};
}

double eval_cubic(const std::array<double, 4>& c, double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }

// Candidate times: t = 0, 1, and the roots of the cubic in (0, 1), bracketed between the
// roots of its derivative and refined by bisection.
std::vector<double> candidate_times(const std::array<double, 4>& c) {
    std::vector<double> knots = {0.0, 1.0};
    const double a = 3 * c[3], b = 2 * c[2], cc = c[1];
    if (a != 0.0) {
        const double disc = b * b - 4 * a * cc;
        if (disc >= 0) {
            const double s = std::sqrt(disc);
            for (double r : {(-b - s) / (2 * a), (-b + s) / (2 * a)})
                if (r > 0 && r < 1) knots.push_back(r);
        }
    } else if (b != 0.0) {
        const double r = -cc / b;
        if (r > 0 && r < 1) knots.push_back(r);
    }
    std::sort(knots.begin(), knots.end());
    std::vector<double> out = {0.0, 1.0};
    for (size_t i = 0; i + 1 < knots.size(); ++i) {
        double lo = knots[i], hi = knots[i + 1];
        double flo = eval_cubic(c, lo), fhi = eval_cubic(c, hi);
        if (flo == 0.0) out.push_back(lo);
        if ((flo < 0) == (fhi < 0)) continue;
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            const double fm = eval_cubic(c, mid);
            if ((fm < 0) == (flo < 0)) {
                lo = mid;
                flo = fm;
            } else {
                hi = mid;
            }
        }
        out.push_back(0.5 * (lo + hi));
    }
    return out;
}

Vec3 lerp(const Vec3& x0, const Vec3& x1, double t) { return x0 + t * (x1 - x0); }

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Ericson's closest point on a triangle.
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return norm(ap);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return norm(bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + (d1 / (d1 - d3)) * ab));
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return norm(cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + (d2 / (d2 - d6)) * ac));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return norm(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
    const double denom = 1.0 / (va + vb + vc);
    return norm(p - (a + (vb * denom) * ab + (vc * denom) * ac));
}

double segment_segment_distance(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
    const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    double s = 0, t = 0;
    if (a <= 1e-300 && e <= 1e-300) return norm(r);
    if (a <= 1e-300) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = dot(d1, r);
        if (e <= 1e-300) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = dot(d1, d2), denom = a * e - b * b;
            s = denom != 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0) {
                t = 0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1) {
                t = 1;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return norm((p1 + s * d1) - (p2 + t * d2));
}

// Least-squares (u, v) with p ~ a + u (b - a) + v (c - a); false if the face is degenerate.
bool barycentric_estimate(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double& u, double& v) {
    const Vec3 e1 = b - a, e2 = c - a, w = p - a;
    const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2), d1 = dot(e1, w), d2 = dot(e2, w);
    const double den = d11 * d22 - d12 * d12;
    if (!(den > 0.0)) return false;
    u = (d22 * d1 - d12 * d2) / den;
    v = (d11 * d2 - d12 * d1) / den;
    return std::isfinite(u) && std::isfinite(v);
}

// (u, v) with a + u (b - a) ~ c + v (d - c) (closest points of the lines); false if parallel.
bool segment_parameters(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& u, double& v) {
    const Vec3 d1 = b - a, d2 = d - c, r = a - c;
    const double A = dot(d1, d1), B = dot(d1, d2), C = dot(d2, d2), D = dot(d1, r), E = dot(d2, r);
    const double den = A * C - B * B;
    if (!(den > 0.0)) return false;
    u = (B * E - C * D) / den;
    v = (A * E - B * D) / den;
    return std::isfinite(u) && std::isfinite(v);
}

constexpr double kFloatTolerance = 1e-9;  // relative to the size of the configuration

// Exact mode runs a shallow conservative filter, the exact static predicates at t = 0 and 1,
// the planar vertex-segment proofs, the certified time-axis test (interval_filter.cpp: proves most near misses apart and most
// contacts), Miranda's test, and only then the exact decision (order and budgets measured
// with `conecull bench ccd`).
// The box filter only drops the clearly separated pairs (boxes down to depth 3, one split per
// parameter): the time-axis test decides near misses and contacts far more cheaply than
// deeper boxes.
constexpr CcdOptions kFilter{1, 15};
constexpr int kTimeAxisBudget = 120;

}  // namespace

ExactPathCounts& exact_path_counts() {
    thread_local ExactPathCounts counts;
    return counts;
}

// The two tests' parameterisations, shared by every mode: F(t, u, v) terms for the inclusion
// search and Miranda (VF: p - a - u (b - a) - v (c - a); EE: a + u (b - a) - c - v (d - c)), and
// the coplanarity cubic det[b - a, c - a, p - a] (VF) / det[b - a, d - c, c - a] (EE).
MovingTerms vertex_face_terms(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                              const Vec3& a1, const Vec3& b1, const Vec3& c1) {
    return {p0 - a0, p1 - a1, a0 - b0, a1 - b1, a0 - c0, a1 - c1, 2.0 * max_abs({p0, a0, b0, c0, p1, a1, b1, c1})};
}
MovingTerms edge_edge_terms(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                            const Vec3& b1, const Vec3& c1, const Vec3& d1) {
    return {a0 - c0, a1 - c1, b0 - a0, b1 - a1, c0 - d0, c1 - d1, 2.0 * max_abs({a0, b0, c0, d0, a1, b1, c1, d1})};
}
std::array<double, 4> vertex_face_cubic(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0,
                                        const Vec3& p1, const Vec3& a1, const Vec3& b1, const Vec3& c1) {
    const Vec3 ba0 = b0 - a0, ca0 = c0 - a0, pa0 = p0 - a0;
    return cubic_of(ba0, (b1 - a1) - ba0, ca0, (c1 - a1) - ca0, pa0, (p1 - a1) - pa0);
}
std::array<double, 4> edge_edge_cubic(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0,
                                      const Vec3& a1, const Vec3& b1, const Vec3& c1, const Vec3& d1) {
    const Vec3 ba0 = b0 - a0, dc0 = d0 - c0, ca0 = c0 - a0;
    return cubic_of(ba0, (b1 - a1) - ba0, dc0, (d1 - c1) - dc0, ca0, (c1 - a1) - ca0);
}

// exact_ccd.cpp
bool vertex_face_ccd_exact(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                           const Vec3& a1, const Vec3& b1, const Vec3& c1);
bool edge_edge_ccd_exact(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                         const Vec3& b1, const Vec3& c1, const Vec3& d1);

// ---- canonical corner order ------------------------------------------------------------------
//
// Float and conservative answers to a near miss depend on which corner is the base of F and of
// the cubic (a review measured 1199 of 200,000 near-miss rows answered differently with a face's
// corners rotated). Each test therefore first orders its primitives' corners by their
// coordinates, so that its answer is a function of the moving points alone: the same whatever
// order a face or an edge stores them in, whichever edge comes first, and however the mesh
// numbers its vertices. Exact answers never depended on it; their path counters now do not
// either. Every test is symmetric in these orders (contact of a point with a closed triangle,
// of two closed segments), so reordering never changes what is being decided.
namespace {

// A moving point: where it starts and where it ends (pointers: the order is chosen, then the
// test reads the caller's vectors).
struct Moving {
    const Vec3* at0;
    const Vec3* at1;
};

// A total order on finite doubles: <, and -0 before +0 (so equal keys are identical bits).
int compare_coordinate(double a, double b) {
    if (a < b) return -1;
    if (b < a) return 1;
    return static_cast<int>(std::signbit(b)) - static_cast<int>(std::signbit(a));
}
// Moving points by start position, then end position, coordinates lexicographically.
int compare_moving(const Moving& p, const Moving& q) {
    for (int i = 0; i < 3; ++i)
        if (const int c = compare_coordinate((*p.at0)[i], (*q.at0)[i])) return c;
    for (int i = 0; i < 3; ++i)
        if (const int c = compare_coordinate((*p.at1)[i], (*q.at1)[i])) return c;
    return 0;
}
// p before q. Branch on the rare tie only: which corner comes first is as random as the mesh,
// so the answer is selected, not branched on.
bool precedes(const Moving& p, const Moving& q) {
    if (p.at0->x != q.at0->x) return p.at0->x < q.at0->x;
    return compare_moving(p, q) < 0;
}
void order_pair(Moving& p, Moving& q) {
    const bool swap = precedes(q, p);
    const Moving lo = swap ? q : p, hi = swap ? p : q;
    p = lo;
    q = hi;
}
// A face's corners sorted (a three-element sorting network).
void order_face(Moving& a, Moving& b, Moving& c) {
    order_pair(a, b);
    order_pair(b, c);
    order_pair(a, b);
}
// Edge (c, d) before edge (a, b), each with its ends sorted: by first ends, then by second
// ends (branching, as in precedes, on the rare tie only).
bool edge_precedes(const Moving& c, const Moving& d, const Moving& a, const Moving& b) {
    if (c.at0->x != a.at0->x) return c.at0->x < a.at0->x;
    const int first = compare_moving(c, a);
    return first < 0 || (first == 0 && compare_moving(d, b) < 0);
}
// Each edge's ends sorted, then the edges.
void order_edges(Moving& a, Moving& b, Moving& c, Moving& d) {
    order_pair(a, b);
    order_pair(c, d);
    const bool swap = edge_precedes(c, d, a, b);
    const Moving a2 = swap ? c : a, b2 = swap ? d : b, c2 = swap ? a : c, d2 = swap ? b : d;
    a = a2, b = b2, c = c2, d = d2;
}

// The tests on corners already in canonical order.
bool vertex_face_ccd_ordered(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                             const Vec3& a1, const Vec3& b1, const Vec3& c1, Arithmetic mode, const CcdOptions& opt);
bool edge_edge_ccd_ordered(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                           const Vec3& b1, const Vec3& c1, const Vec3& d1, Arithmetic mode, const CcdOptions& opt);

}  // namespace

bool vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1, const Vec3& a1,
                     const Vec3& b1, const Vec3& c1, Arithmetic mode, const CcdOptions& opt) {
    Moving a{&a0, &a1}, b{&b0, &b1}, c{&c0, &c1};
    order_face(a, b, c);
    return vertex_face_ccd_ordered(p0, *a.at0, *b.at0, *c.at0, p1, *a.at1, *b.at1, *c.at1, mode, opt);
}

bool edge_edge_ccd(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1, const Vec3& b1,
                   const Vec3& c1, const Vec3& d1, Arithmetic mode, const CcdOptions& opt) {
    Moving a{&a0, &a1}, b{&b0, &b1}, c{&c0, &c1}, d{&d0, &d1};
    order_edges(a, b, c, d);
    return edge_edge_ccd_ordered(*a.at0, *b.at0, *c.at0, *d.at0, *a.at1, *b.at1, *c.at1, *d.at1, mode, opt);
}

namespace {

bool vertex_face_ccd_ordered(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                             const Vec3& a1, const Vec3& b1, const Vec3& c1, Arithmetic mode, const CcdOptions& opt) {
    if (mode == Arithmetic::kConservative) {
        const MovingTerms m = vertex_face_terms(p0, a0, b0, c0, p1, a1, b1, c1);
        return inclusion_search(m, true, opt);
    }
    if (mode == Arithmetic::kFloat) {
        const auto cubic = vertex_face_cubic(p0, a0, b0, c0, p1, a1, b1, c1);
        const double size = std::max(1e-300, max_abs({b0 - a0, c0 - a0, p0 - a0, b1 - a1, c1 - a1, p1 - a1}));
        for (double t : candidate_times(cubic))
            if (point_triangle_distance(lerp(p0, p1, t), lerp(a0, a1, t), lerp(b0, b1, t), lerp(c0, c1, t)) <=
                kFloatTolerance * size)
                return true;
        return false;
    }
    // exact: the conservative filter never misses, so its "no" is final; the certified tests'
    // proofs (apart or contact) are final too; the rest is decided exactly.
    ExactPathCounts& counts = exact_path_counts();
    if (!vertex_face_ccd_ordered(p0, a0, b0, c0, p1, a1, b1, c1, Arithmetic::kConservative, kFilter))
        return ++counts.filtered, false;
    // Contact at t = 0 or t = 1: exact static predicates.
    if (segment_meets_triangle(p0, p0, a0, b0, c0) || segment_meets_triangle(p1, p1, a1, b1, c1))
        return ++counts.static_contact, true;
    // p crossing an edge of the face (all in an axis-aligned plane): a contact on the boundary,
    // which the time-axis test below would chase to its depth limit. Free when no coordinate
    // is shared.
    if (vertex_segment_planar_contact(p0, a0, b0, p1, a1, b1, kTimeAxisBudget) == TimeAxisVerdict::kContact ||
        vertex_segment_planar_contact(p0, b0, c0, p1, b1, c1, kTimeAxisBudget) == TimeAxisVerdict::kContact ||
        vertex_segment_planar_contact(p0, c0, a0, p1, c1, a1, kTimeAxisBudget) == TimeAxisVerdict::kContact)
        return ++counts.proven_contact, true;
    switch (vertex_face_time_axis(p0, a0, b0, c0, p1, a1, b1, c1, kTimeAxisBudget)) {
        case TimeAxisVerdict::kApart: return ++counts.interval_filtered, false;
        case TimeAxisVerdict::kContact: return ++counts.proven_contact, true;
        case TimeAxisVerdict::kUnknown: break;
    }
    {
        const MovingTerms m = vertex_face_terms(p0, a0, b0, c0, p1, a1, b1, c1);
        const auto cubic = vertex_face_cubic(p0, a0, b0, c0, p1, a1, b1, c1);
        for (double t : candidate_times(cubic)) {
            double u, v;
            if (barycentric_estimate(lerp(p0, p1, t), lerp(a0, a1, t), lerp(b0, b1, t), lerp(c0, c1, t), u, v) &&
                miranda_contact(m, true, t, u, v))
                return ++counts.proven_contact, true;
        }
    }
    ++counts.exact_engine;
    return vertex_face_ccd_exact(p0, a0, b0, c0, p1, a1, b1, c1);
}

bool edge_edge_ccd_ordered(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                           const Vec3& b1, const Vec3& c1, const Vec3& d1, Arithmetic mode, const CcdOptions& opt) {
    if (mode == Arithmetic::kConservative) {
        const MovingTerms m = edge_edge_terms(a0, b0, c0, d0, a1, b1, c1, d1);
        return inclusion_search(m, false, opt);
    }
    if (mode == Arithmetic::kFloat) {
        const auto cubic = edge_edge_cubic(a0, b0, c0, d0, a1, b1, c1, d1);
        const double size = std::max(1e-300, max_abs({b0 - a0, d0 - c0, c0 - a0, b1 - a1, d1 - c1, c1 - a1}));
        for (double t : candidate_times(cubic))
            if (segment_segment_distance(lerp(a0, a1, t), lerp(b0, b1, t), lerp(c0, c1, t), lerp(d0, d1, t)) <=
                kFloatTolerance * size)
                return true;
        return false;
    }
    ExactPathCounts& counts = exact_path_counts();
    if (!edge_edge_ccd_ordered(a0, b0, c0, d0, a1, b1, c1, d1, Arithmetic::kConservative, kFilter))
        return ++counts.filtered, false;
    if (segment_meets_segment(a0, b0, c0, d0) || segment_meets_segment(a1, b1, c1, d1)) return ++counts.static_contact, true;
    // An endpoint crossing the other segment (all in an axis-aligned plane): a contact on the
    // boundary (see VF).
    if (vertex_segment_planar_contact(a0, c0, d0, a1, c1, d1, kTimeAxisBudget) == TimeAxisVerdict::kContact ||
        vertex_segment_planar_contact(b0, c0, d0, b1, c1, d1, kTimeAxisBudget) == TimeAxisVerdict::kContact ||
        vertex_segment_planar_contact(c0, a0, b0, c1, a1, b1, kTimeAxisBudget) == TimeAxisVerdict::kContact ||
        vertex_segment_planar_contact(d0, a0, b0, d1, a1, b1, kTimeAxisBudget) == TimeAxisVerdict::kContact)
        return ++counts.proven_contact, true;
    switch (edge_edge_time_axis(a0, b0, c0, d0, a1, b1, c1, d1, kTimeAxisBudget)) {
        case TimeAxisVerdict::kApart: return ++counts.interval_filtered, false;
        case TimeAxisVerdict::kContact: return ++counts.proven_contact, true;
        case TimeAxisVerdict::kUnknown: break;
    }
    {
        const MovingTerms m = edge_edge_terms(a0, b0, c0, d0, a1, b1, c1, d1);
        const auto cubic = edge_edge_cubic(a0, b0, c0, d0, a1, b1, c1, d1);
        for (double t : candidate_times(cubic)) {
            double u, v;
            if (segment_parameters(lerp(a0, a1, t), lerp(b0, b1, t), lerp(c0, c1, t), lerp(d0, d1, t), u, v) &&
                miranda_contact(m, false, t, u, v))
                return ++counts.proven_contact, true;
        }
    }
    ++counts.exact_engine;
    return edge_edge_ccd_exact(a0, b0, c0, d0, a1, b1, c1, d1);
}

}  // namespace

// The lower bounds order corners as the tests do (the same bound whatever the storage order).
double vertex_face_toi_lower_bound(const Vec3& p0, const Vec3& a0_in, const Vec3& b0_in, const Vec3& c0_in,
                                   const Vec3& p1, const Vec3& a1_in, const Vec3& b1_in, const Vec3& c1_in) {
    Moving a{&a0_in, &a1_in}, b{&b0_in, &b1_in}, c{&c0_in, &c1_in};
    order_face(a, b, c);
    const MovingTerms m = vertex_face_terms(p0, *a.at0, *b.at0, *c.at0, p1, *a.at1, *b.at1, *c.at1);
    double t = 1.0;
    return inclusion_search(m, true, CcdOptions{20, 20000}, &t) ? t : 1.0;
}

double edge_edge_toi_lower_bound(const Vec3& a0_in, const Vec3& b0_in, const Vec3& c0_in, const Vec3& d0_in,
                                 const Vec3& a1_in, const Vec3& b1_in, const Vec3& c1_in, const Vec3& d1_in) {
    Moving a{&a0_in, &a1_in}, b{&b0_in, &b1_in}, c{&c0_in, &c1_in}, d{&d0_in, &d1_in};
    order_edges(a, b, c, d);
    const MovingTerms m = edge_edge_terms(*a.at0, *b.at0, *c.at0, *d.at0, *a.at1, *b.at1, *c.at1, *d.at1);
    double t = 1.0;
    return inclusion_search(m, false, CcdOptions{20, 20000}, &t) ? t : 1.0;
}

}  // namespace conecull
