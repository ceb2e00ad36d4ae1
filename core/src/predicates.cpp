// Exact fallbacks of the filtered predicates in predicates/orient.hpp.
#include "conecull/predicates/orient.hpp"

namespace conecull::detail {

using namespace conecull::exact;

namespace {

// det[[p0 p1 p2]; [q0 q1 q2]; [r0 r1 r2]] (rows p, q, r) = p . (q x r), for expansions.
template <int P, int Q, int R>
int det3_sign(const Expansion<P> (&p)[3], const Expansion<Q> (&q)[3], const Expansion<R> (&r)[3]) {
    const auto c0 = sub(mul(q[1], r[2]), mul(q[2], r[1]));
    const auto c1 = sub(mul(q[2], r[0]), mul(q[0], r[2]));
    const auto c2 = sub(mul(q[0], r[1]), mul(q[1], r[0]));
    const auto s = add(add(mul(p[0], c0), mul(p[1], c1)), mul(p[2], c2));
    return sign(s);
}

// Rows p - q as expansions: one double each when every difference rounded exactly (Sterbenz:
// nearby coordinates, the usual case at a near-degenerate input), so the expansion products stay
// small; two doubles each otherwise.
template <int K>
void differences(const Vec3 (&p)[K], const Vec3 (&q)[K], Expansion<1> (&one)[K][3], Expansion<2> (&two)[K][3],
                 bool& exact) {
    exact = true;
    for (int r = 0; r < K; ++r)
        for (int k = 0; k < 3; ++k) {
            two[r][k] = difference(p[r][k], q[r][k]);
            exact = exact && two[r][k].n <= 1;
            one[r][k] = value(p[r][k] - q[r][k]);
        }
}

}  // namespace

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    // Two equal points make the determinant exactly 0. Adjacent triangles ask this often (a
    // shared vertex passed twice), and the filter can never prove a zero: skip the expansions.
    if (a == b || a == c || a == d || b == c || b == d || c == d) return 0;
    // ((b - a) x (c - a)) . (d - a) = det[d - a; b - a; c - a]
    Expansion<1> one[3][3];
    Expansion<2> two[3][3];
    bool exact;
    differences<3>({d, b, c}, {a, a, a}, one, two, exact);
    return exact ? det3_sign(one[0], one[1], one[2]) : det3_sign(two[0], two[1], two[2]);
}

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
    if ((ax == bx && ay == by) || (ax == cx && ay == cy) || (bx == cx && by == cy)) return 0;  // as orient3d_exact
    const auto bax = difference(bx, ax), cay = difference(cy, ay), bay = difference(by, ay), cax = difference(cx, ax);
    if (bax.n <= 1 && cay.n <= 1 && bay.n <= 1 && cax.n <= 1)  // exact differences, as differences()
        return sign(sub(mul(value(bx - ax), value(cy - ay)), mul(value(by - ay), value(cx - ax))));
    return sign(sub(mul(bax, cay), mul(bay, cax)));
}

int side_sign_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& l) {
    // ((a - c) x (b - c)) . l = det[l; a - c; b - c]
    const Expansion<1> ll[3] = {value(l.x), value(l.y), value(l.z)};
    Expansion<1> one[2][3];
    Expansion<2> two[2][3];
    bool exact;
    differences<2>({a, b}, {c, c}, one, two, exact);
    return exact ? det3_sign(ll, one[0], one[1]) : det3_sign(ll, two[0], two[1]);
}

int ray_side_sign_exact(const Vec3& v, const Vec3& o, const Vec3& r, const Vec3& l) {
    // (r x (v - o)) . l = det[l; r; v - o]
    const Expansion<1> ll[3] = {value(l.x), value(l.y), value(l.z)};
    const Expansion<1> rr[3] = {value(r.x), value(r.y), value(r.z)};
    Expansion<1> one[1][3];
    Expansion<2> two[1][3];
    bool exact;
    differences<1>({v}, {o}, one, two, exact);
    return exact ? det3_sign(ll, rr, one[0]) : det3_sign(ll, rr, two[0]);
}

}  // namespace conecull::detail

// ---- sums of determinants (predicates/det_sum.hpp) -------------------------------------
#include "conecull/predicates/det_sum.hpp"

namespace conecull::detail {

namespace {

using namespace conecull::exact;

Expansion<2> diff_k(const DetRow& r, int k) { return difference(r.head[k], r.tail[k]); }

// det of one Det3 as an expansion (capacity 192, see det3_sign above).
Expansion<192> det_expansion(const Det3& d) {
    const Expansion<2> p[3] = {diff_k(d.r0, 0), diff_k(d.r0, 1), diff_k(d.r0, 2)};
    const Expansion<2> q[3] = {diff_k(d.r1, 0), diff_k(d.r1, 1), diff_k(d.r1, 2)};
    const Expansion<2> r[3] = {diff_k(d.r2, 0), diff_k(d.r2, 1), diff_k(d.r2, 2)};
    const auto c0 = sub(mul(q[1], r[2]), mul(q[2], r[1]));
    const auto c1 = sub(mul(q[2], r[0]), mul(q[0], r[2]));
    const auto c2 = sub(mul(q[0], r[1]), mul(q[1], r[0]));
    return add(add(mul(p[0], c0), mul(p[1], c1)), mul(p[2], c2));
}

}  // namespace

int det_sum_sign_exact(const Det3* dets, int m) {
    // At most 3 determinants in this library; accumulate pairwise into a fixed capacity.
    Expansion<576> acc;
    for (int k = 0; k < m && k < 3; ++k) {
        const auto s = add(acc, det_expansion(dets[k]));
        for (int i = 0; i < s.n; ++i) acc.c[i] = s.c[i];
        acc.n = s.n;
    }
    return sign(acc);
}

}  // namespace conecull::detail
