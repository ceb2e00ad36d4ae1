// A certified "no contact" filter on the time axis, for pairs the box subdivision cannot
// exclude (near misses). A contact at time t needs the coplanarity polynomial f(t) = 0 and, at
// that t, necessary sign conditions on a few polynomials (below). With interval arithmetic
// (every rounding widens the result outward), [0, 1] is covered by t-intervals on each of
// which f provably has no root or a necessary condition provably fails. Then there is no
// contact. Anything not proven stays for the exact decision.
//
// Necessary conditions (derived in the comments of each test; checked by the exact tests):
//   VF, p in the closed triangle abc: for every axis k, o_k n_k >= 0 with n = (b-a) x (c-a) and
//     o one of (b-a) x (p-a), (c-b) x (p-b), (a-c) x (p-c): each o equals a barycentric
//     coordinate times n.
//   EE, [a,b] meets [c,d] at a + u(b-a) = c + v(d-c): ((b-a) x (c-a))_k ((b-a) x (d-a))_k =
//     -v (1-v) ((b-a) x (d-c))_k^2 <= 0, and likewise with the segments swapped.
#include <algorithm>
#include <cmath>
#include <vector>

#include "conecull/vec3.hpp"

namespace conecull {

namespace {

// [lo, hi] with every operation rounded outward: the exact result of the operation on any
// points of the operands lies inside. A computed double is within 2^-53 |x| (+ a subnormal
// ulp) of the exact value, so widening by 2^-52 |x| + 2^-1000 is safe.
struct Interval {
    double lo = 0.0, hi = 0.0;
    static Interval widen(double a, double b) {
        const double l = std::min(a, b), h = std::max(a, b);
        return {l - (std::fabs(l) * 0x1p-52 + 0x1p-1000), h + (std::fabs(h) * 0x1p-52 + 0x1p-1000)};
    }
};
Interval exact(double x) { return {x, x}; }
Interval operator+(const Interval& a, const Interval& b) { return Interval::widen(a.lo + b.lo, a.hi + b.hi); }
Interval operator-(const Interval& a, const Interval& b) { return Interval::widen(a.lo - b.hi, a.hi - b.lo); }
Interval operator*(const Interval& a, const Interval& b) {
    const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    return Interval::widen(*std::min_element(p, p + 4), *std::max_element(p, p + 4));
}

using IPoly = std::vector<Interval>;  // power basis, low to high

IPoly add(const IPoly& a, const IPoly& b) {
    IPoly r(std::max(a.size(), b.size()), exact(0.0));
    for (size_t i = 0; i < r.size(); ++i) {
        if (i < a.size() && i < b.size()) r[i] = a[i] + b[i];
        else r[i] = i < a.size() ? a[i] : b[i];
    }
    return r;
}
IPoly sub(const IPoly& a, const IPoly& b) {
    IPoly nb = b;
    for (auto& x : nb) x = {-x.hi, -x.lo};
    return add(a, nb);
}
IPoly mul(const IPoly& a, const IPoly& b) {
    IPoly r(a.size() + b.size() - 1, exact(0.0));
    for (size_t i = 0; i < a.size(); ++i)
        for (size_t j = 0; j < b.size(); ++j) r[i + j] = r[i + j] + a[i] * b[j];
    return r;
}
// Range of p over t in [t0, t1] (Horner in interval arithmetic).
Interval range(const IPoly& p, double t0, double t1) {
    const Interval t{t0, t1};
    Interval r = exact(0.0);
    for (size_t i = p.size(); i-- > 0;) r = r * t + p[i];
    return r;
}

struct IVec {
    IPoly c[3];
};
IVec moving(const Vec3& x0, const Vec3& x1) {
    IVec v;
    for (int k = 0; k < 3; ++k) v.c[k] = {exact(x0[k]), exact(x1[k]) - exact(x0[k])};
    return v;
}
IVec operator-(const IVec& a, const IVec& b) {
    IVec r;
    for (int k = 0; k < 3; ++k) r.c[k] = sub(a.c[k], b.c[k]);
    return r;
}
IVec cross(const IVec& a, const IVec& b) {
    IVec r;
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        r.c[k] = sub(mul(a.c[i], b.c[j]), mul(a.c[j], b.c[i]));
    }
    return r;
}
IPoly dot(const IVec& a, const IVec& b) { return add(add(mul(a.c[0], b.c[0]), mul(a.c[1], b.c[1])), mul(a.c[2], b.c[2])); }

// Covers [0, 1]: each piece must show f != 0 or one of `must_be_nonneg` < 0 (as given).
bool excluded_on_unit(const IPoly& f, const std::vector<IPoly>& must_be_nonneg, int budget) {
    std::vector<std::pair<double, double>> stack = {{0.0, 1.0}};
    int pieces = 0;
    while (!stack.empty()) {
        const auto [t0, t1] = stack.back();
        stack.pop_back();
        if (++pieces > budget) return false;
        const Interval F = range(f, t0, t1);
        if (F.lo > 0.0 || F.hi < 0.0) continue;
        bool fails = false;
        for (const IPoly& h : must_be_nonneg)
            if (range(h, t0, t1).hi < 0.0) {
                fails = true;
                break;
            }
        if (fails) continue;
        if (t1 - t0 < 0x1p-40) return false;
        const double m = 0.5 * (t0 + t1);
        stack.push_back({m, t1});
        stack.push_back({t0, m});
    }
    return true;
}

}  // namespace

bool vertex_face_certainly_apart(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                                 const Vec3& a1, const Vec3& b1, const Vec3& c1) {
    const IVec p = moving(p0, p1), a = moving(a0, a1), b = moving(b0, b1), c = moving(c0, c1);
    const IVec n = cross(b - a, c - a);
    const IPoly f = dot(n, p - a);
    const IVec o[3] = {cross(b - a, p - a), cross(c - b, p - b), cross(a - c, p - c)};
    std::vector<IPoly> conditions;
    for (const IVec& oi : o)
        for (int k = 0; k < 3; ++k) conditions.push_back(mul(oi.c[k], n.c[k]));
    return excluded_on_unit(f, conditions, 120);
}

bool edge_edge_certainly_apart(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                               const Vec3& b1, const Vec3& c1, const Vec3& d1) {
    const IVec a = moving(a0, a1), b = moving(b0, b1), c = moving(c0, c1), d = moving(d0, d1);
    const IPoly f = dot(cross(b - a, d - c), c - a);
    const IVec T1 = cross(b - a, c - a), T2 = cross(b - a, d - a), T3 = cross(d - c, a - c), T4 = cross(d - c, b - c);
    std::vector<IPoly> conditions;  // -(T1 T2) >= 0 and -(T3 T4) >= 0 on every axis
    for (int k = 0; k < 3; ++k) {
        conditions.push_back(sub(IPoly{exact(0.0)}, mul(T1.c[k], T2.c[k])));
        conditions.push_back(sub(IPoly{exact(0.0)}, mul(T3.c[k], T4.c[k])));
    }
    return excluded_on_unit(f, conditions, 120);
}

}  // namespace conecull
