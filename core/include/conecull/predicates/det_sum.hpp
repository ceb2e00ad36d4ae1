// Exact sign of a sum of 3x3 determinants whose rows are differences of double points
// (row = head - tail; tail = 0 for an exact vector such as a cone axis). The CCD formulas are
// such sums: the middle Bernstein coefficient of a quadratic side function (Sec. 3.6, k_1) and
// the inner coefficients of the coplanarity cubic of the non-penetration filter.
#pragma once

#include <cmath>

#include "conecull/predicates/orient.hpp"

namespace conecull {

struct DetRow {
    Vec3 head, tail;  // the row is head - tail, evaluated exactly
};
struct Det3 {
    DetRow r0, r1, r2;
};

namespace detail {
int det_sum_sign_exact(const Det3* dets, int m);
}

// sign(sum_k det[r0; r1; r2]_k). Filter: a determinant's monomials carry at most 8 rounding
// factors (a difference each, a product, a difference, the product with the third difference,
// two sums; a product carries both factors'), and each of the m - 1 further sums one more: the
// computed sum is within gamma_(7 + m) of the sum of permanents, whose computed value is at
// least (1 - eps)^(7 + m) of it. (8 + m) eps covers both with margin. (Shewchuk's 7 eps for one
// orient3d lets the last rounding go free against the computed value; here the last sum of a
// determinant is not the last operation.)
template <int M>
int det_sum_sign(const Det3 (&dets)[M]) {
    static_assert(M >= 1 && M <= 3, "the exact fallback holds up to three determinants");
    constexpr int m = M;
    double sum = 0.0, perm = 0.0;
    for (int k = 0; k < m; ++k) {
        const Det3& d = dets[k];
        const Vec3 p = d.r0.head - d.r0.tail, q = d.r1.head - d.r1.tail, r = d.r2.head - d.r2.tail;
        const double m1 = q.y * r.z, m2 = q.z * r.y, m3 = q.z * r.x, m4 = q.x * r.z, m5 = q.x * r.y, m6 = q.y * r.x;
        sum += p.x * (m1 - m2) + p.y * (m3 - m4) + p.z * (m5 - m6);
        perm += std::fabs(p.x) * (std::fabs(m1) + std::fabs(m2)) + std::fabs(p.y) * (std::fabs(m3) + std::fabs(m4)) +
                std::fabs(p.z) * (std::fabs(m5) + std::fabs(m6));
    }
    const double bound = (8.0 + m) * kEps * perm;
    if (sum > bound) return 1;
    if (-sum > bound) return -1;
    return detail::det_sum_sign_exact(dets, m);
}

}  // namespace conecull
