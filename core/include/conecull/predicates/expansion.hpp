// Exact floating-point expansion arithmetic (Shewchuk, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates", 1997): a value is an unevaluated sum of
// non-overlapping doubles ordered by increasing magnitude, so its sign is the sign of the
// last (largest) component. Exact as long as nothing overflows or underflows; the bindings
// restrict coordinates to [2^-128, 2^128] in magnitude (or 0) so that degree-4 products of
// coordinate differences stay far inside the double range.
//
// Requires IEEE round-to-nearest and no contraction of a*b+c into FMA (CMake passes
// -ffp-contract=off); never compile this with -ffast-math.
#pragma once

#include <cstddef>

namespace conecull::exact {

// Capacity is a compile-time bound; n is the number of live components.
template <int N>
struct Expansion {
    static constexpr int capacity = N;
    double c[N];
    int n = 0;
};

inline void two_sum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bv = x - a;
    const double av = x - bv;
    y = (a - av) + (b - bv);
}

inline void fast_two_sum(double a, double b, double& x, double& y) {  // |a| >= |b|
    x = a + b;
    y = b - (x - a);
}

inline void two_diff(double a, double b, double& x, double& y) {
    x = a - b;
    const double bv = a - x;
    const double av = x + bv;
    y = (a - av) + (bv - b);
}

// Dekker split: a = hi + lo with hi, lo holding at most 26 significant bits each.
inline void split(double a, double& hi, double& lo) {
    constexpr double splitter = 134217729.0;  // 2^27 + 1
    const double c = splitter * a;
    const double abig = c - a;
    hi = c - abig;
    lo = a - hi;
}

inline void two_product(double a, double b, double& x, double& y) {
    x = a * b;
    double ahi, alo, bhi, blo;
    split(a, ahi, alo);
    split(b, bhi, blo);
    const double err1 = x - ahi * bhi;
    const double err2 = err1 - alo * bhi;
    const double err3 = err2 - ahi * blo;
    y = alo * blo - err3;
}

inline Expansion<1> value(double a) {
    Expansion<1> e;
    if (a != 0.0) e.c[e.n++] = a;
    return e;
}

inline Expansion<2> difference(double a, double b) {
    Expansion<2> e;
    double x, y;
    two_diff(a, b, x, y);
    if (y != 0.0) e.c[e.n++] = y;
    if (x != 0.0) e.c[e.n++] = x;
    return e;
}

template <int A>
Expansion<A> negate(const Expansion<A>& e) {
    Expansion<A> r;
    r.n = e.n;
    for (int i = 0; i < e.n; ++i) r.c[i] = -e.c[i];
    return r;
}

// Shewchuk's FAST-EXPANSION-SUM-ZEROELIM.
template <int A, int B>
Expansion<A + B> add(const Expansion<A>& e, const Expansion<B>& f) {
    Expansion<A + B> h;
    if (e.n == 0) {
        for (int i = 0; i < f.n; ++i) h.c[i] = f.c[i];
        h.n = f.n;
        return h;
    }
    if (f.n == 0) {
        for (int i = 0; i < e.n; ++i) h.c[i] = e.c[i];
        h.n = e.n;
        return h;
    }
    int ei = 0, fi = 0;
    double enow = e.c[0], fnow = f.c[0];
    double q, qnew, hh;
    if ((fnow > enow) == (fnow > -enow)) {
        q = enow;
        enow = (++ei < e.n) ? e.c[ei] : 0.0;
    } else {
        q = fnow;
        fnow = (++fi < f.n) ? f.c[fi] : 0.0;
    }
    if (ei < e.n && fi < f.n) {
        if ((fnow > enow) == (fnow > -enow)) {
            fast_two_sum(enow, q, qnew, hh);
            enow = (++ei < e.n) ? e.c[ei] : 0.0;
        } else {
            fast_two_sum(fnow, q, qnew, hh);
            fnow = (++fi < f.n) ? f.c[fi] : 0.0;
        }
        q = qnew;
        if (hh != 0.0) h.c[h.n++] = hh;
        while (ei < e.n && fi < f.n) {
            if ((fnow > enow) == (fnow > -enow)) {
                two_sum(q, enow, qnew, hh);
                enow = (++ei < e.n) ? e.c[ei] : 0.0;
            } else {
                two_sum(q, fnow, qnew, hh);
                fnow = (++fi < f.n) ? f.c[fi] : 0.0;
            }
            q = qnew;
            if (hh != 0.0) h.c[h.n++] = hh;
        }
    }
    while (ei < e.n) {
        two_sum(q, enow, qnew, hh);
        enow = (++ei < e.n) ? e.c[ei] : 0.0;
        q = qnew;
        if (hh != 0.0) h.c[h.n++] = hh;
    }
    while (fi < f.n) {
        two_sum(q, fnow, qnew, hh);
        fnow = (++fi < f.n) ? f.c[fi] : 0.0;
        q = qnew;
        if (hh != 0.0) h.c[h.n++] = hh;
    }
    if (q != 0.0 || h.n == 0) h.c[h.n++] = q;
    if (h.n == 1 && h.c[0] == 0.0) h.n = 0;
    return h;
}

template <int A, int B>
Expansion<A + B> sub(const Expansion<A>& e, const Expansion<B>& f) {
    return add(e, negate(f));
}

// Shewchuk's SCALE-EXPANSION-ZEROELIM: e * b.
template <int A>
Expansion<2 * A> scale(const Expansion<A>& e, double b) {
    Expansion<2 * A> h;
    if (e.n == 0 || b == 0.0) return h;
    double q, hh, product1, product0, sum;
    two_product(e.c[0], b, q, hh);
    if (hh != 0.0) h.c[h.n++] = hh;
    for (int i = 1; i < e.n; ++i) {
        two_product(e.c[i], b, product1, product0);
        two_sum(q, product0, sum, hh);
        if (hh != 0.0) h.c[h.n++] = hh;
        fast_two_sum(product1, sum, q, hh);
        if (hh != 0.0) h.c[h.n++] = hh;
    }
    if (q != 0.0 || h.n == 0) h.c[h.n++] = q;
    if (h.n == 1 && h.c[0] == 0.0) h.n = 0;
    return h;
}

// e * f as the sum over f's components of e scaled by each.
template <int A, int B>
Expansion<2 * A * B> mul(const Expansion<A>& e, const Expansion<B>& f) {
    Expansion<2 * A * B> acc;
    for (int i = 0; i < f.n; ++i) {
        const Expansion<2 * A> t = scale(e, f.c[i]);
        Expansion<2 * A * B> next;
        // acc has at most 2*A*i live components here, so the sum fits the capacity.
        const auto s = add(acc, t);
        for (int k = 0; k < s.n; ++k) next.c[k] = s.c[k];
        next.n = s.n;
        acc = next;
    }
    return acc;
}

template <int A>
int sign(const Expansion<A>& e) {
    if (e.n == 0) return 0;
    const double top = e.c[e.n - 1];
    return (top > 0.0) - (top < 0.0);
}

template <int A>
double estimate(const Expansion<A>& e) {
    double s = 0.0;
    for (int i = 0; i < e.n; ++i) s += e.c[i];
    return s;
}

}  // namespace conecull::exact
