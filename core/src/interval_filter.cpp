// A certified time-axis test for the pairs the shallow box subdivision cannot exclude (near
// misses and contacts). A contact at time t needs the coplanarity polynomial f(t) = 0 and, at
// that t, necessary sign conditions h >= 0 on a few polynomials (below). With interval
// arithmetic (every rounding widens the result outward), [0, 1] is covered by t-intervals on
// each of which f provably has no root or a necessary condition provably fails: then there is
// no contact. Conversely, a piece on which f provably changes sign and the conditions are
// provably > 0 in the pattern below holds a contact (intermediate value theorem). Anything
// not proven stays for Miranda's test and the exact decision.
//
// Conditions (checked by the exact tests):
//   VF: n = (b-a) x (c-a) and o one of (b-a) x (p-a), (c-b) x (p-b), (a-c) x (p-c). When p is
//     in the plane of abc, o = lambda n with lambda p's barycentric coordinate opposite that
//     edge, so o_k n_k = lambda n_k^2. p in the closed triangle: o_k n_k >= 0 for every o and
//     axis k (necessary). Some axis k with o_k n_k > 0 for all three o: every lambda > 0, p
//     strictly inside (sufficient, with coplanarity).
//   EE: with all four points coplanar, T1 = (b-a) x (c-a) and T2 = (b-a) x (d-a) are normal
//     to the common plane. If [a,b] meets [c,d] at a + u(b-a) = c + v(d-c), then
//     T1_k T2_k = -v (1-v) ((b-a) x (d-c))_k^2 <= 0 (necessary), likewise T3 = (d-c) x (a-c),
//     T4 = (d-c) x (b-c). Some axis with T1_k T2_k < 0: T1, T2 are antiparallel, c and d lie
//     strictly on opposite sides of the line ab in the plane; with some axis where
//     T3_k T4_k < 0 too, each segment crosses the other's line at an interior point, and the
//     two lines meet in one point: a contact (sufficient, with coplanarity).
//
// Every polynomial is kept in Bernstein form on the current piece [t0, t1] (its value is a
// convex combination of the coefficients, so their hull bounds its range: far tighter than
// interval Horner, hence fewer pieces; the first and last coefficients are its values at t0
// and t1), built straight from the positions at t = 0 and t = 1 (a moving difference has the
// Bernstein coefficients q0 - r0, q1 - r1: no velocity is rounded) and split at the midpoint
// by de Casteljau's algorithm. Fixed degrees (f cubic, the conditions quartic): everything
// lives on the stack.
#include <algorithm>
#include <cmath>

#include "conecull/ccd/interval_filter.hpp"

namespace conecull {

namespace {

// [lo, hi] with every operation rounded outward: the exact result of the operation on any
// points of the operands lies inside. A computed double is within 2^-53 |x| (+ a subnormal
// ulp) of the exact value, so widening by 2^-52 |x| + 2^-1000 is safe.
struct Interval {
    double lo, hi;  // no initializers: the piece stack below stays uninitialised until written
    static Interval widen(double a, double b) {
        const double l = std::min(a, b), h = std::max(a, b);
        return {l - (std::fabs(l) * 0x1p-52 + 0x1p-1000), h + (std::fabs(h) * 0x1p-52 + 0x1p-1000)};
    }
};
Interval operator+(const Interval& a, const Interval& b) { return Interval::widen(a.lo + b.lo, a.hi + b.hi); }
Interval operator-(const Interval& a, const Interval& b) { return Interval::widen(a.lo - b.hi, a.hi - b.lo); }
Interval operator*(const Interval& a, const Interval& b) {
    const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    return Interval::widen(std::min({p[0], p[1], p[2], p[3]}), std::max({p[0], p[1], p[2], p[3]}));
}
// a / k for an integer k > 0: one correctly rounded division per end, widened like the rest.
Interval divided(const Interval& a, double k) { return Interval::widen(a.lo / k, a.hi / k); }
// (a + b) / 2: the sum is rounded once (covered by the widening); halving is exact except in
// the subnormal range, where the 2^-1000 term covers it.
Interval midpoint(const Interval& a, const Interval& b) { return Interval::widen(0.5 * (a.lo + b.lo), 0.5 * (a.hi + b.hi)); }

// The setup's arithmetic: a computed value and its permanent (the same expression on the inputs'
// absolute values, subtractions made additions). Every polynomial of the setup has degree <= 4
// in the differences q - r of two positions, and those are the only inputs. With coordinates 0
// or in [2^-128, 2^128] (checked where positions enter), every difference is a multiple of
// 2^-180 and at most 2^129, and every intermediate is 0 or at least 2^-780 and at most 2^540:
// no operation underflows or overflows, halving is exact, and each other operation rounds with
// a relative error of at most u = 2^-53. Expanded into monomials of the exact differences, each
// coefficient's monomials carry at most K factors (1 + delta), |delta| <= u: a difference
// brings one, a sum or difference of two values one more than the larger count, a product the
// counts of both factors plus one (Higham, Lemma 3.3: the factors' errors multiply, so a
// product of four rounded differences carries 7, not the 3 of its longest path). `Roundings`
// below makes the compiler count K for the very expressions the setup computes (15: f 12, the
// conditions 15, counting x + x as a rounding) and the build fails if a change makes it exceed
// kSetupRoundings. So |v - exact| <= gamma_K P (Higham, Sec. 3.1) with P the exact permanent,
// and the computed permanent p >= P (1 - u)^K. For K <= 15, as 16 (1 - 15u)(1 - u)^15 > 15:
// |v - exact| <= 15u / ((1 - 15u)(1 - u)^15) p < 16u p = 2^-49 p, an exact product:
// `enclosed` below. Why: rounding each of the setup's ~200 interval products outward took half
// of exact CCD's time on the n-body step; here each costs two plain products. (Until the
// twenty-seventh session this comment counted the roundings along one path, K = 10, and the
// bound was 11u p: too small in the worst case.) Tested against fractions in
// tests/ccd/test_time_axis_enclosures.py.
struct Approx {
    double v, p;
};
Approx operator+(const Approx& a, const Approx& b) { return {a.v + b.v, a.p + b.p}; }
Approx operator-(const Approx& a, const Approx& b) { return {a.v - b.v, a.p + b.p}; }
Approx operator*(const Approx& a, const Approx& b) { return {a.v * b.v, a.p * b.p}; }
Approx divided(const Approx& a, double k) { return {a.v / k, a.p / k}; }
Approx midpoint(const Approx& a, const Approx& b) { return {0.5 * (a.v + b.v), 0.5 * (a.p + b.p)}; }
Interval negated(const Interval& a) { return {-a.hi, -a.lo}; }
Approx negated(const Approx& a) { return {-a.v, a.p}; }
// The rounding counts of the proof above: a coefficient's most (1 + delta) factors on any of its
// monomials. Only the compiler evaluates these (static_assert below).
struct Roundings {
    int k;
};
constexpr Roundings operator+(Roundings a, Roundings b) { return {std::max(a.k, b.k) + 1}; }
constexpr Roundings operator-(Roundings a, Roundings b) { return {std::max(a.k, b.k) + 1}; }
constexpr Roundings operator*(Roundings a, Roundings b) { return {a.k + b.k + 1}; }
constexpr Roundings divided(Roundings a, double) { return {a.k + 1}; }
constexpr Roundings midpoint(Roundings a, Roundings b) { return {std::max(a.k, b.k) + 1}; }  // halving exact
constexpr Roundings negated(Roundings a) { return a; }
constexpr int kSetupRoundings = 15;  // the K that `enclosed`'s 16u covers
// The interval the bound above gives (its own two roundings covered by widen).
Interval enclosed(const Approx& a) {
    const double e = a.p * 0x1p-49;  // 16 u, exact: a power of two
    return Interval::widen(a.v - e, a.v + e);
}

// Bernstein coefficients b_0..b_D of a polynomial of degree <= D on the current piece: intervals
// in the search; Approx while the setup builds them (lo, hi and split are the search's).
template <int D, class T = Interval>
struct Bern {
    T b[D + 1];
    // Hull of the coefficients: contains the polynomial's range on the piece.
    double lo() const {
        double m = b[0].lo;
        for (int i = 1; i <= D; ++i) m = std::min(m, b[i].lo);
        return m;
    }
    double hi() const {
        double m = b[0].hi;
        for (int i = 1; i <= D; ++i) m = std::max(m, b[i].hi);
        return m;
    }
    // de Casteljau at s = 1/2: the coefficients on the left and right halves of the piece.
    void split(Bern& left, Bern& right) const {
        Interval w[D + 1];
        std::copy(b, b + D + 1, w);
        left.b[0] = w[0];
        right.b[D] = w[D];
        for (int r = 1; r <= D; ++r) {
            for (int i = 0; i + r <= D; ++i) w[i] = midpoint(w[i], w[i + 1]);
            left.b[r] = w[0];
            right.b[D - r] = w[D - r];
        }
    }
};

// Products in Bernstein form on [0, 1]: for p = sum a_i B_i^m and q = sum b_j B_j^n,
// pq = sum_k c_k B_k^(m+n) with c_k = sum_{i+j=k} C(m,i) C(n,j) a_i b_j / C(m+n,k).
template <class T>
constexpr Bern<2, T> mul(const Bern<1, T>& a, const Bern<1, T>& b) {
    return {{a.b[0] * b.b[0], midpoint(a.b[0] * b.b[1], a.b[1] * b.b[0]), a.b[1] * b.b[1]}};
}
template <class T>
constexpr Bern<3, T> mul(const Bern<2, T>& a, const Bern<1, T>& b) {
    const T c1 = (a.b[1] * b.b[0] + a.b[1] * b.b[0]) + a.b[0] * b.b[1];  // 2 a1 b0 + a0 b1
    const T c2 = a.b[2] * b.b[0] + (a.b[1] * b.b[1] + a.b[1] * b.b[1]);  // a2 b0 + 2 a1 b1
    return {{a.b[0] * b.b[0], divided(c1, 3.0), divided(c2, 3.0), a.b[2] * b.b[1]}};
}
template <class T>
constexpr Bern<4, T> mul(const Bern<2, T>& a, const Bern<2, T>& b) {
    const T m11 = a.b[1] * b.b[1];
    const T c2 = (a.b[0] * b.b[2] + a.b[2] * b.b[0]) + ((m11 + m11) + (m11 + m11));  // a0 b2 + 4 a1 b1 + a2 b0
    return {{a.b[0] * b.b[0], midpoint(a.b[0] * b.b[1], a.b[1] * b.b[0]), divided(c2, 6.0),
             midpoint(a.b[1] * b.b[2], a.b[2] * b.b[1]), a.b[2] * b.b[2]}};
}
template <int D, class T>
constexpr Bern<D, T> operator+(const Bern<D, T>& a, const Bern<D, T>& b) {
    Bern<D, T> r{};
    for (int i = 0; i <= D; ++i) r.b[i] = a.b[i] + b.b[i];
    return r;
}
template <int D, class T>
constexpr Bern<D, T> operator-(const Bern<D, T>& a, const Bern<D, T>& b) {
    Bern<D, T> r{};
    for (int i = 0; i <= D; ++i) r.b[i] = a.b[i] - b.b[i];
    return r;
}
template <int D, class T>
constexpr Bern<D, T> negated(const Bern<D, T>& a) {
    Bern<D, T> r{};
    for (int i = 0; i <= D; ++i) r.b[i] = negated(a.b[i]);
    return r;
}
template <int D>
Bern<D> enclosed(const Bern<D, Approx>& a) {
    Bern<D> r;
    for (int i = 0; i <= D; ++i) r.b[i] = enclosed(a.b[i]);
    return r;
}

// A moving difference q(t) - r(t), per axis linear: Bernstein coefficients q0 - r0, q1 - r1.
template <class T>
struct LinVec {
    Bern<1, T> c[3];
};
template <class T>
struct QuadVec {
    Bern<2, T> c[3];
};
// One rounded difference of two coordinates, as each arithmetic holds it.
template <class T>
T rounded(double d);
template <>
Interval rounded<Interval>(double d) { return Interval::widen(d, d); }
template <>
Approx rounded<Approx>(double d) { return {d, std::fabs(d)}; }
template <class T>
LinVec<T> difference(const Vec3& q0, const Vec3& q1, const Vec3& r0, const Vec3& r1) {
    LinVec<T> v;
    for (int k = 0; k < 3; ++k) v.c[k] = {{rounded<T>(q0[k] - r0[k]), rounded<T>(q1[k] - r1[k])}};
    return v;
}
template <class T>
constexpr Bern<2, T> dot2(const LinVec<T>& a, const LinVec<T>& b, int i, int j) {
    return mul(a.c[i], b.c[i]) + mul(a.c[j], b.c[j]);
}
template <class T>
constexpr QuadVec<T> cross(const LinVec<T>& a, const LinVec<T>& b) {
    QuadVec<T> r{};
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        r.c[k] = mul(a.c[i], b.c[j]) - mul(a.c[j], b.c[i]);
    }
    return r;
}
template <class T>
constexpr Bern<3, T> dot(const QuadVec<T>& a, const LinVec<T>& b) {
    return mul(a.c[0], b.c[0]) + mul(a.c[1], b.c[1]) + mul(a.c[2], b.c[2]);
}

// Depth-first over pieces of [0, 1], left to right. A piece is done when f != 0 on it or a
// condition h < 0 on it (no contact there); a contact is proven on a piece where f takes
// opposite strict signs at its ends and `sufficient` holds for its conditions. A piece at the
// depth limit still undecided, or the budget running out: not proven.
template <int DF, int DH, int N, class Sufficient>
TimeAxisVerdict search_unit(const Bern<DF>& f0, const Bern<DH> (&h0)[N], int budget, Sufficient sufficient) {
    struct Piece {
        Bern<DF> f;
        Bern<DH> h[N];
        int depth;
    };
    // Pieces of 2^-30: a contact on the boundary of the domain (a condition exactly 0 at the
    // root) is never decided, and the descent to this depth is its cost.
    constexpr int kMaxDepth = 30;
    Piece stack[kMaxDepth + 2];  // depth-first: at most one pending sibling per level
    int top = 0;
    stack[top].f = f0;
    std::copy(h0, h0 + N, stack[top].h);
    stack[top++].depth = 0;
    int pieces = 0;
    while (top > 0) {
        const Piece& p = stack[--top];
        if (++pieces > budget) return TimeAxisVerdict::kUnknown;
        if (p.f.lo() > 0.0 || p.f.hi() < 0.0) continue;
        double hlo[N];
        bool fails = false;
        for (int i = 0; i < N && !fails; ++i) {
            fails = p.h[i].hi() < 0.0;
            hlo[i] = p.h[i].lo();
        }
        if (fails) continue;
        const Interval& fa = p.f.b[0];
        const Interval& fb = p.f.b[DF];  // f(t0), f(t1)
        if (((fa.hi < 0.0 && fb.lo > 0.0) || (fa.lo > 0.0 && fb.hi < 0.0)) && sufficient(hlo))
            return TimeAxisVerdict::kContact;
        if (p.depth >= kMaxDepth) return TimeAxisVerdict::kUnknown;
        // Split into the slots top (right half, pending) and top + 1 (left half, next);
        // p lives in slot top, so split through a copy.
        const Piece whole = p;
        Piece& right = stack[top];
        Piece& left = stack[top + 1];
        whole.f.split(left.f, right.f);
        for (int i = 0; i < N; ++i) whole.h[i].split(left.h[i], right.h[i]);
        left.depth = right.depth = whole.depth + 1;
        top += 2;
    }
    return TimeAxisVerdict::kApart;
}

// The polynomials the searches start from, the cubic f and N conditions h, in any of the
// arithmetics above: the positions enter as the differences they use.
template <class T, int N>
struct StartPolys {
    Bern<3, T> f;
    Bern<4, T> h[N];
};
template <class T>
using VertexFacePolys = StartPolys<T, 9>;
template <class T>
using EdgeEdgePolys = StartPolys<T, 6>;
template <class T>
constexpr VertexFacePolys<T> vertex_face_polys(const LinVec<T>& ba, const LinVec<T>& ca, const LinVec<T>& pa,
                                               const LinVec<T>& cb, const LinVec<T>& pb, const LinVec<T>& ac,
                                               const LinVec<T>& pc) {
    VertexFacePolys<T> s{};
    const QuadVec<T> n = cross(ba, ca);
    s.f = dot(n, pa);
    const QuadVec<T> o[3] = {cross(ba, pa), cross(cb, pb), cross(ac, pc)};
    for (int i = 0; i < 3; ++i)  // h[3 i + k] = o_i,k n_k
        for (int k = 0; k < 3; ++k) s.h[3 * i + k] = mul(o[i].c[k], n.c[k]);
    return s;
}
template <class T>
constexpr EdgeEdgePolys<T> edge_edge_polys(const LinVec<T>& ba, const LinVec<T>& dc, const LinVec<T>& ca,
                                           const LinVec<T>& da, const LinVec<T>& ac, const LinVec<T>& bc) {
    EdgeEdgePolys<T> s{};
    s.f = dot(cross(ba, dc), ca);
    const QuadVec<T> T1 = cross(ba, ca), T2 = cross(ba, da), T3 = cross(dc, ac), T4 = cross(dc, bc);
    for (int k = 0; k < 3; ++k) {  // h[2 k] = -(T1 T2)_k, h[2 k + 1] = -(T3 T4)_k
        s.h[2 * k] = negated(mul(T1.c[k], T2.c[k]));
        s.h[2 * k + 1] = negated(mul(T3.c[k], T4.c[k]));
    }
    return s;
}

// The proof's K, counted by the compiler on the expressions above: every difference one rounding.
template <class Polys>
constexpr int most_roundings(const Polys& s) {
    int k = 0;
    for (const Roundings& c : s.f.b) k = std::max(k, c.k);
    for (const auto& h : s.h)
        for (const Roundings& c : h.b) k = std::max(k, c.k);
    return k;
}
constexpr LinVec<Roundings> kDifference{{{{{1}, {1}}}, {{{1}, {1}}}, {{{1}, {1}}}}};
constexpr int kVertexFaceRoundings = most_roundings(
    vertex_face_polys(kDifference, kDifference, kDifference, kDifference, kDifference, kDifference, kDifference));
constexpr int kEdgeEdgeRoundings = most_roundings(
    edge_edge_polys(kDifference, kDifference, kDifference, kDifference, kDifference, kDifference));
static_assert(kVertexFaceRoundings <= kSetupRoundings && kEdgeEdgeRoundings <= kSetupRoundings,
              "the setup rounds more often than enclosed()'s bound covers: rederive its constant");

// The enclosures on [0, 1] the searches start from: the polynomials in the setup's arithmetic
// (above), each coefficient enclosed once at the end.
template <int N>
StartPolys<Interval, N> enclosed(const StartPolys<Approx, N>& x) {
    StartPolys<Interval, N> s;
    s.f = enclosed(x.f);
    for (int i = 0; i < N; ++i) s.h[i] = enclosed(x.h[i]);
    return s;
}
VertexFacePolys<Interval> vertex_face_start(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0,
                                            const Vec3& p1, const Vec3& a1, const Vec3& b1, const Vec3& c1) {
    using A = Approx;
    return enclosed(vertex_face_polys(difference<A>(b0, b1, a0, a1), difference<A>(c0, c1, a0, a1),
                                      difference<A>(p0, p1, a0, a1), difference<A>(c0, c1, b0, b1),
                                      difference<A>(p0, p1, b0, b1), difference<A>(a0, a1, c0, c1),
                                      difference<A>(p0, p1, c0, c1)));
}
EdgeEdgePolys<Interval> edge_edge_start(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0,
                                        const Vec3& a1, const Vec3& b1, const Vec3& c1, const Vec3& d1) {
    using A = Approx;
    return enclosed(edge_edge_polys(difference<A>(b0, b1, a0, a1), difference<A>(d0, d1, c0, c1),
                                    difference<A>(c0, c1, a0, a1), difference<A>(d0, d1, a0, a1),
                                    difference<A>(a0, a1, c0, c1), difference<A>(b0, b1, c0, c1)));
}

template <int DF, int DH, int N>
void flatten(const Bern<DF>& f, const Bern<DH> (&h)[N], double* lo, double* hi) {
    for (int i = 0; i <= DF; ++i) *lo++ = f.b[i].lo, *hi++ = f.b[i].hi;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i <= DH; ++i) *lo++ = h[j].b[i].lo, *hi++ = h[j].b[i].hi;
}

}  // namespace

void time_axis_enclosures(bool vertex_face, const Vec3 (&x)[8], double* lo, double* hi) {
    if (vertex_face) {
        const auto s = vertex_face_start(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]);
        flatten(s.f, s.h, lo, hi);
    } else {
        const auto s = edge_edge_start(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]);
        flatten(s.f, s.h, lo, hi);
    }
}

TimeAxisVerdict vertex_face_time_axis(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                                      const Vec3& a1, const Vec3& b1, const Vec3& c1, int budget) {
    const auto s = vertex_face_start(p0, a0, b0, c0, p1, a1, b1, c1);
    // p strictly inside: one axis k on which all three o_i,k n_k > 0.
    const auto inside = [](const double* lo) {
        for (int k = 0; k < 3; ++k)
            if (lo[k] > 0.0 && lo[3 + k] > 0.0 && lo[6 + k] > 0.0) return true;
        return false;
    };
    return search_unit(s.f, s.h, budget, inside);
}

TimeAxisVerdict edge_edge_time_axis(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                                    const Vec3& b1, const Vec3& c1, const Vec3& d1, int budget) {
    const auto s = edge_edge_start(a0, b0, c0, d0, a1, b1, c1, d1);
    // c, d strictly on opposite sides of line ab (some axis), and a, b of line cd (some axis).
    const auto crossing = [](const double* lo) {
        return (lo[0] > 0.0 || lo[2] > 0.0 || lo[4] > 0.0) && (lo[1] > 0.0 || lo[3] > 0.0 || lo[5] > 0.0);
    };
    return search_unit(s.f, s.h, budget, crossing);
}

TimeAxisVerdict vertex_segment_planar_contact(const Vec3& q0, const Vec3& x0, const Vec3& y0, const Vec3& q1,
                                              const Vec3& x1, const Vec3& y1, int budget) {
    // An axis k on which q, x, y agree exactly at t = 0 and at t = 1: then they agree at every
    // t (linear motion), and the problem lives in the plane of the other two axes i, j.
    int k = 0;
    while (k < 3 && !(q0[k] == x0[k] && q0[k] == y0[k] && q1[k] == x1[k] && q1[k] == y1[k])) ++k;
    if (k == 3) return TimeAxisVerdict::kUnknown;
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    using I = Interval;
    const LinVec<I> yx = difference<I>(y0, y1, x0, x1), qx = difference<I>(q0, q1, x0, x1);
    const LinVec<I> xy = difference<I>(x0, x1, y0, y1), qy = difference<I>(q0, q1, y0, y1);
    // g = (y - x) x (q - x) in the plane: q on the line xy iff g = 0 (given x != y). On that
    // line q = x + s (y - x), and (q - x).(y - x) = s |y - x|^2 > 0 with
    // (q - y).(x - y) = (1 - s) |y - x|^2 > 0 give s in (0, 1): q inside the segment.
    const Bern<2> g = mul(yx.c[i], qx.c[j]) - mul(yx.c[j], qx.c[i]);
    const Bern<2> h[2] = {dot2(qx, yx, i, j), dot2(qy, xy, i, j)};
    const auto between = [](const double* lo) { return lo[0] > 0.0 && lo[1] > 0.0; };
    // Only a proven contact counts: "apart" here says nothing about the rest of the pair.
    return search_unit(g, h, budget, between) == TimeAxisVerdict::kContact ? TimeAxisVerdict::kContact
                                                                            : TimeAxisVerdict::kUnknown;
}

}  // namespace conecull
