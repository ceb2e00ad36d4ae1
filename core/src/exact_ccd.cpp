// Exact CCD decisions (the fallback of arithmetic="exact"): polynomials in t with exact dyadic
// coefficients, exact real-root isolation in [0, 1], and signs of polynomials at those roots.
//
// A vertex-face or edge-edge pair is in contact at time t iff P(t) holds, where P is a boolean
// function of the signs of a fixed, finite set of polynomials in t (coplanarity f, projected
// orientations, coordinate differences). The set S = {t in [0, 1] : P(t)} is closed, so if it
// is not empty it contains t = 0, t = 1, or a root of one of those polynomials (the left end of
// any of its intervals is such a point). When f is not identically zero, S lies in the roots
// of f. So: evaluate P exactly at those finitely many points.
#include <stdexcept>
#include <vector>

#include "conecull/ccd/elementary_ccd.hpp"
#include "conecull/exact/dyadic.hpp"

namespace conecull {

namespace {

using exact::Dyadic;
using Poly = std::vector<Dyadic>;  // power basis, low to high, no trailing zeros

void trim(Poly& p) {
    while (!p.empty() && p.back().is_zero()) p.pop_back();
}
int degree(const Poly& p) { return static_cast<int>(p.size()) - 1; }

Poly add(const Poly& a, const Poly& b) {
    Poly r(std::max(a.size(), b.size()));
    for (size_t i = 0; i < r.size(); ++i) r[i] = (i < a.size() ? a[i] : Dyadic()) + (i < b.size() ? b[i] : Dyadic());
    trim(r);
    return r;
}
Poly neg(Poly a) {
    for (auto& x : a) x = -x;
    return a;
}
Poly sub(const Poly& a, const Poly& b) { return add(a, neg(b)); }
Poly mul(const Poly& a, const Poly& b) {
    if (a.empty() || b.empty()) return {};
    Poly r(a.size() + b.size() - 1);
    for (size_t i = 0; i < a.size(); ++i)
        for (size_t j = 0; j < b.size(); ++j) r[i + j] = r[i + j] + a[i] * b[j];
    trim(r);
    return r;
}
Poly scale(const Poly& a, const Dyadic& s) {
    Poly r = a;
    for (auto& x : r) x = x * s;
    trim(r);
    return r;
}
Poly shift_up(const Poly& a, int d) {  // a * t^d
    if (a.empty()) return a;
    Poly r(d, Dyadic());
    r.insert(r.end(), a.begin(), a.end());
    return r;
}
Dyadic eval(const Poly& p, const Dyadic& t) {
    Dyadic r;
    for (size_t i = p.size(); i-- > 0;) r = r * t + p[i];
    return r;
}
Poly derivative(const Poly& p) {
    Poly r;
    for (size_t i = 1; i < p.size(); ++i) r.push_back(p[i] * Dyadic(static_cast<double>(i)));
    trim(r);
    return r;
}

// A multiple of the remainder of A by B (pseudo-division: only ring operations).
Poly prem(Poly R, const Poly& B) {
    const Dyadic lb = B.back();
    while (!R.empty() && degree(R) >= degree(B)) {
        const int d = degree(R) - degree(B);
        R = sub(scale(R, lb), shift_up(scale(B, R.back()), d));
    }
    return R;
}

// gcd up to a constant factor.
Poly gcd(Poly A, Poly B) {
    while (!B.empty()) {
        Poly R = prem(A, B);
        A = std::move(B);
        B = std::move(R);
    }
    return A;
}

// Q with lc(B)^k A = Q B, when B divides A.
Poly exact_quotient(Poly R, const Poly& B) {
    const Dyadic lb = B.back();
    Poly Q;
    while (!R.empty() && degree(R) >= degree(B)) {
        const int d = degree(R) - degree(B);
        const Poly T = shift_up(Poly{R.back()}, d);
        R = sub(scale(R, lb), mul(T, B));
        Q = add(scale(Q, lb), T);
    }
    if (!R.empty()) throw std::logic_error("exact_quotient: not divisible");
    return Q;
}

Poly squarefree(const Poly& h) {
    const Poly g = gcd(h, derivative(h));
    return degree(g) <= 0 ? h : exact_quotient(h, g);
}

// Sign variations of the Bernstein coefficients of p on [lo, hi] (scaled by binomials, which
// keeps signs): an upper bound on the number of roots in (lo, hi) with the same parity
// (Descartes' rule in Bernstein form). Also reports whether all are non-zero and of one sign.
int variations(const Poly& p, const Dyadic& lo, const Dyadic& hi, int* uniform_sign = nullptr) {
    const int n = degree(p);
    // q(s) = p(lo + (hi - lo) s)
    const Poly lin = {lo, hi - lo};
    Poly q;
    for (size_t i = p.size(); i-- > 0;) q = add(mul(q, lin), Poly{p[i]});
    q.resize(n + 1);
    static const double C[5][5] = {{1, 0, 0, 0, 0}, {1, 1, 0, 0, 0}, {1, 2, 1, 0, 0}, {1, 3, 3, 1, 0}, {1, 4, 6, 4, 1}};
    if (n > 4) throw std::logic_error("variations: degree above 4");
    int changes = 0, last = 0, first = 0;
    bool uniform = true;
    for (int i = 0; i <= n; ++i) {
        Dyadic b;
        for (int j = 0; j <= i; ++j) b = b + q[j] * Dyadic(C[n - j][i - j]);
        const int s = b.sign();
        if (s == 0) uniform = false;
        if (i == 0) first = s;
        if (s != 0 && last != 0 && s != last) changes++;
        if (s != 0) last = s;
        if (s != first) uniform = false;
    }
    if (uniform_sign) *uniform_sign = uniform ? first : 0;
    return changes;
}

constexpr int kMaxRefinements = 4000;  // exact bisection of a squarefree polynomial ends long before

// A point of [0, 1]: rational, or the unique root of squarefree h in the open (lo, hi) with
// h(lo), h(hi) non-zero.
struct Point {
    bool rational = true;
    Dyadic t, lo, hi;
    Poly h;
    int refinements = 0;

    void bisect() {
        if (++refinements > kMaxRefinements) throw std::runtime_error("exact CCD: root refinement did not converge");
        const Dyadic mid = (lo + hi).half();
        const int sm = eval(h, mid).sign();
        if (sm == 0) {
            rational = true;
            t = mid;
            return;
        }
        if (sm * eval(h, lo).sign() < 0) hi = mid;
        else lo = mid;
    }

    int sign(const Poly& q) {
        if (q.empty()) return 0;
        // Usually q keeps one sign near the root: a few bisections show it without any gcd.
        for (int i = 0; i < 12; ++i) {
            if (rational) return eval(q, t).sign();
            int s = 0;
            variations(q, lo, hi, &s);
            if (s != 0) return s;
            bisect();
        }
        if (rational) return eval(q, t).sign();
        const Poly g = gcd(h, q);
        if (degree(g) >= 1) {
            // g divides h, so it is squarefree and can only vanish in (lo, hi) at our root.
            for (;;) {
                if (rational) return eval(q, t).sign();
                const int v = variations(g, lo, hi);
                if (v == 1 && eval(g, lo).sign() * eval(g, hi).sign() < 0) return 0;
                if (v == 0) break;
                bisect();
            }
        }
        for (;;) {
            if (rational) return eval(q, t).sign();
            int s = 0;
            variations(q, lo, hi, &s);
            if (s != 0) return s;
            bisect();
        }
    }
};

void isolate(const Poly& h, const Dyadic& lo, const Dyadic& hi, std::vector<Point>& out, int depth) {
    if (depth > kMaxRefinements) throw std::runtime_error("exact CCD: root isolation did not converge");
    const int v = variations(h, lo, hi);
    if (v == 0) return;
    if (v == 1 && !eval(h, lo).is_zero() && !eval(h, hi).is_zero()) {
        Point p;
        p.rational = false;
        p.h = h;
        p.lo = lo;
        p.hi = hi;
        out.push_back(std::move(p));
        return;
    }
    const Dyadic mid = (lo + hi).half();
    if (eval(h, mid).is_zero()) {
        Point p;
        p.t = mid;
        out.push_back(std::move(p));
    }
    isolate(h, lo, mid, out, depth + 1);
    isolate(h, mid, hi, out, depth + 1);
}

// Roots of a non-zero polynomial in [0, 1].
void roots_in_unit(const Poly& p, std::vector<Point>& out) {
    if (degree(p) < 1) return;
    const Poly h = squarefree(p);
    const Dyadic zero, one(1.0);
    for (const Dyadic& e : {zero, one}) {
        if (eval(h, e).is_zero()) {
            Point q;
            q.t = e;
            out.push_back(std::move(q));
        }
    }
    isolate(h, zero, one, out, 0);
}

struct LVec {
    Poly c[3];
};
LVec moving(const Vec3& x0, const Vec3& x1) {
    LVec v;
    for (int k = 0; k < 3; ++k) {
        const Dyadic a(x0[k]), b(x1[k]);
        v.c[k] = {a, b - a};
        trim(v.c[k]);
    }
    return v;
}
LVec operator-(const LVec& a, const LVec& b) {
    LVec r;
    for (int k = 0; k < 3; ++k) r.c[k] = sub(a.c[k], b.c[k]);
    return r;
}
LVec cross(const LVec& a, const LVec& b) {
    LVec r;
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        r.c[k] = sub(mul(a.c[i], b.c[j]), mul(a.c[j], b.c[i]));
    }
    return r;
}
Poly dot(const LVec& a, const LVec& b) { return add(add(mul(a.c[0], b.c[0]), mul(a.c[1], b.c[1])), mul(a.c[2], b.c[2])); }

template <class Predicate>
bool holds_somewhere(const Poly& f, const std::vector<const Poly*>& critical, Predicate P) {
    std::vector<Point> pts;
    if (!f.empty()) {
        roots_in_unit(f, pts);  // P needs f = 0
    } else {
        Point z, o;
        z.t = Dyadic();
        o.t = Dyadic(1.0);
        pts.push_back(z);
        pts.push_back(o);
        for (const Poly* q : critical) roots_in_unit(*q, pts);
    }
    for (Point& pt : pts)
        if (P(pt)) return true;
    return false;
}

}  // namespace

bool vertex_face_ccd_exact(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                           const Vec3& a1, const Vec3& b1, const Vec3& c1) {
    const LVec p = moving(p0, p1), a = moving(a0, a1), b = moving(b0, b1), c = moving(c0, c1);
    const LVec n = cross(b - a, c - a);
    const LVec o1 = cross(b - a, p - a), o2 = cross(c - b, p - b), o3 = cross(a - c, p - c);
    const Poly f = dot(n, p - a);  // coplanarity of p with the face
    const LVec pa = p - a, pb = p - b, pc = p - c;
    auto inside = [&](Point& t) {
        if (t.sign(f) != 0) return false;
        for (int k = 0; k < 3; ++k) {
            const int s = t.sign(n.c[k]);
            if (s != 0) return t.sign(o1.c[k]) * s >= 0 && t.sign(o2.c[k]) * s >= 0 && t.sign(o3.c[k]) * s >= 0;
        }
        // Degenerate face at t (a segment or a point): p must lie on one of its edges.
        auto on_edge = [&](const LVec& o, const LVec& px, const LVec& py) {
            for (int k = 0; k < 3; ++k)
                if (t.sign(o.c[k]) != 0) return false;
            for (int j = 0; j < 3; ++j)
                if (t.sign(px.c[j]) * t.sign(py.c[j]) > 0) return false;
            return true;
        };
        return on_edge(o1, pa, pb) || on_edge(o2, pb, pc) || on_edge(o3, pc, pa);
    };
    std::vector<const Poly*> crit;
    for (const LVec* v : {&n, &o1, &o2, &o3, &pa, &pb, &pc})
        for (const Poly& q : v->c) crit.push_back(&q);
    return holds_somewhere(f, crit, inside);
}

bool edge_edge_ccd_exact(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                         const Vec3& b1, const Vec3& c1, const Vec3& d1) {
    const LVec a = moving(a0, a1), b = moving(b0, b1), c = moving(c0, c1), d = moving(d0, d1);
    const Poly f = dot(cross(b - a, d - c), c - a);
    const LVec T1 = cross(b - a, c - a), T2 = cross(b - a, d - a), T3 = cross(d - c, a - c), T4 = cross(d - c, b - c);
    const LVec* pts[4] = {&a, &b, &c, &d};
    LVec diff[4][4];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (i != j) diff[i][j] = *pts[i] - *pts[j];
    auto meet = [&](Point& t) {
        if (t.sign(f) != 0) return false;
        // x (index) lies in the box of y, z along the two coordinates kept by projection k
        auto in_box = [&](int x, int y, int z, int k) {
            for (int j : {(k + 1) % 3, (k + 2) % 3})
                if (t.sign(diff[x][y].c[j]) * t.sign(diff[x][z].c[j]) > 0) return false;
            return true;
        };
        for (const LVec* T : {&T1, &T2, &T3, &T4}) {
            for (int k = 0; k < 3; ++k) {
                if (t.sign(T->c[k]) == 0) continue;
                // segments_meet_2d(a, b, c, d) in the projection dropping axis k
                const int s1 = t.sign(T3.c[k]), s2 = t.sign(T4.c[k]), s3 = t.sign(T1.c[k]), s4 = t.sign(T2.c[k]);
                if (s1 * s2 < 0 && s3 * s4 < 0) return true;
                return (s1 == 0 && in_box(0, 2, 3, k)) || (s2 == 0 && in_box(1, 2, 3, k)) ||
                       (s3 == 0 && in_box(2, 0, 1, k)) || (s4 == 0 && in_box(3, 0, 1, k));
            }
        }
        // All four collinear (or coincident): intervals along an axis where they spread.
        for (int k = 0; k < 3; ++k) {
            bool spread = false;
            for (int i = 0; i < 4 && !spread; ++i)
                for (int j = i + 1; j < 4 && !spread; ++j) spread = t.sign(diff[i][j].c[k]) != 0;
            if (!spread) continue;
            auto less = [&](int x, int y) { return t.sign(diff[x][y].c[k]) < 0; };
            const bool ab_before_cd = less(0, 2) && less(0, 3) && less(1, 2) && less(1, 3);
            const bool cd_before_ab = less(2, 0) && less(2, 1) && less(3, 0) && less(3, 1);
            return !ab_before_cd && !cd_before_ab;
        }
        return true;  // all four points coincide
    };
    std::vector<const Poly*> crit;
    for (const LVec* v : {&T1, &T2, &T3, &T4})
        for (const Poly& q : v->c) crit.push_back(&q);
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
            for (const Poly& q : diff[i][j].c) crit.push_back(&q);
    return holds_somewhere(f, crit, meet);
}

}  // namespace conecull
