// Kernel points of the star-contour tests. Any point o works for the tests (their signs are
// exact, so "passed" is a proof for whichever o was used); o only decides how often they pass.
//   - kernel_point: Alg. 1 line 2 (and Alg. 3 line 2), the mean of the contour vertices.
//   - search_kernel_point: the line search of [SPO10] ("sct"): project the contour on the plane
//     perpendicular to the cone axis and intersect, along one line, the inner half-planes of
//     all its edges. It finds a kernel point of many loops whose mean lies outside the kernel
//     (long, bent contours of large nodes).
//   - clipped_kernel_point (ours): the kernel of the projected loop itself, clipped from all
//     the edges' half-planes; o the mean of its corners. It finds a kernel point whenever the
//     kernel has an interior, where the mean and the line search look at one point and one line.
//   - find_kernel_point: what the "nc" tests try after the mean: clipped_kernel_point, and the
//     line search when the kernel polygon grows too many corners.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "conecull/vec3.hpp"

namespace conecull {

// A computed kernel point enters the exact predicates like a vertex, so it must lie in their
// domain too: each coordinate 0 or of magnitude in [2^-128, 2^128] (what the bindings demand of
// positions; outside it, products in the expansions could underflow). Any o is valid, so tiny
// coordinates are set to 0; a huge or non-finite one means no usable point (the test fails, not
// culled). The mean needs no check: no larger than the largest vertex coordinate, and a non-zero
// coordinate of it is a rounded multiple of 2^-180 (the vertices' finest grid) over n < 2^31, so at
// least 2^-211 with a grid of 2^-263, coarse enough that no product in the expansions underflows.
inline bool in_predicate_domain(Vec3& o) {
    double* c[3] = {&o.x, &o.y, &o.z};
    for (double* x : c) {
        const double a = std::fabs(*x);
        if (!(a <= 0x1p128)) return false;  // also NaN
        if (a < 0x1p-128) *x = 0.0;
    }
    return true;
}

// Alg. 1 line 2: kernel point o = mean of the contour vertices (of V). Rounding only moves it.
inline Vec3 kernel_point(const int32_t* loop, int32_t n, const double* V) {
    Vec3 sum;
    for (int32_t i = 0; i < n; ++i) sum = sum + load(V, loop[i]);
    return (1.0 / n) * sum;
}

// The frame of the projection plane: u = l x e_k with e_k the axis of l's smallest component,
// so u is exact (its components are +-l's or 0) and exactly perpendicular to l; w = l x u,
// rounded (w_exact is only used in the error analysis). The rays are u + phi e_k.
struct ProjectionFrame {
    Vec3 u, w;
    int k = 0;
    double uu = 0;     // |u|^2 (rounded; only scales the candidate o)
    double scale = 0;  // max(max |u_j|, max |w_j|, max |l_j| max |u_j|): see project()
};

inline ProjectionFrame projection_frame(const Vec3& l) {
    ProjectionFrame f;
    const double ax = std::fabs(l.x), ay = std::fabs(l.y), az = std::fabs(l.z);
    f.k = (ax <= ay && ax <= az) ? 0 : (ay <= az ? 1 : 2);
    f.u = f.k == 0 ? Vec3{0.0, l.z, -l.y} : (f.k == 1 ? Vec3{-l.z, 0.0, l.x} : Vec3{l.y, -l.x, 0.0});
    f.w = cross(l, f.u);
    f.uu = dot(f.u, f.u);
    auto mx = [](const Vec3& a) { return std::fmax(std::fabs(a.x), std::fmax(std::fabs(a.y), std::fabs(a.z))); };
    f.scale = std::fmax(std::fmax(mx(f.u), mx(f.w)), mx(l) * mx(f.u));
    return f;
}

// Scratch buffers reused between tests (one per traversal; never shared between threads).
struct ProjectionScratch {
    std::vector<double> X, Y;
};

// At least n elements of a scratch buffer, their values unspecified. Why not resize(n): loops of
// different lengths take turns, and every resize up zero-fills the elements it adds.
template <class T>
T* scratch_buffer(std::vector<T>& v, size_t n) {
    if (v.size() < n) v.resize(n);
    return v.data();
}

// Projects p relative to the reference vertex c: X = fl(fl(p - c) . u), Y = fl(fl(p - c) . w~).
// With d = fl(p - c) and D1 = |d|_1, the exact projections X* = (p - c) . u, Y* = (p - c) . w
// (w = l x u exactly) satisfy |X - X*| <= (gamma_3 + 1.01 eps) D1 max|u_j| and
// |Y - Y*| <= (gamma_3 + 1.01 eps) D1 max|w~_j| + D1 max|w~_j - w_j| with
// |w~_j - w_j| <= gamma_2 * 2 max|l_j| max|u_j|; so both are within 9 eps D1 scale, and
// delta = 16 eps max(D1) scale bounds every coordinate of the contour (and of o).
inline double project(const Vec3& p, const Vec3& c, const ProjectionFrame& f, double& X, double& Y) {
    const Vec3 d = p - c;
    X = dot(d, f.u);
    Y = dot(d, f.w);
    return std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
}

// The line search of [SPO10] on the projected polygon ("sct" steps 1-2): the loop is projected
// into `s` (X, Y relative to its first vertex) as the search goes, and searched along the line
// Y = Ym through the projection (Xm, Ym) of m (the mean, kernel_point). Edge (a, b) keeps the
// side cross2(b - a, p - a) > 0 for a counter-clockwise polygon (< 0 clockwise); on the line
// that is a half-line bounded by x* = a_x + e_x (Ym - a_y) / e_y. Both orientations are searched
// in the same pass, which stops as soon as both intervals are empty (no kernel point on the
// line). On success o is the 3D point that projects to the middle of the overlap,
// o = m + ((xo - Xm) / |u|^2) u (o may be m itself), and d1 the largest |p - first vertex|_1
// (the error bound of the projections). `visited`: the edges examined.
inline bool search_kernel_point(const int32_t* loop, int32_t n, const double* V, const ProjectionFrame& f,
                                const Vec3& m, ProjectionScratch& s, Vec3& o, double& d1, int32_t& visited) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    double* X = scratch_buffer(s.X, static_cast<size_t>(n));
    double* Y = scratch_buffer(s.Y, static_cast<size_t>(n));
    const Vec3 c = load(V, loop[0]);
    double Xm, Ym;
    project(m, c, f, Xm, Ym);
    d1 = project(c, c, f, X[0], Y[0]);
    double lo[2] = {-inf, -inf}, hi[2] = {inf, inf};  // [0]: counter-clockwise, [1]: clockwise
    for (int32_t i = 0; i < n; ++i) {
        const int32_t j = i + 1 == n ? 0 : i + 1;
        if (j != 0) d1 = max_into(d1, project(load(V, loop[j]), c, f, X[j], Y[j]));
        const double ex = X[j] - X[i], ey = Y[j] - Y[i];
        if (ey == 0.0) {  // edge parallel to the line: all or nothing
            const double side = ex * (Ym - Y[i]);
            if (!(side > 0)) lo[0] = inf;
            if (!(side < 0)) lo[1] = inf;
        } else {
            const double x = X[i] + ex * (Ym - Y[i]) / ey;
            if (ey > 0) {
                hi[0] = min_into(hi[0], x);
                lo[1] = max_into(lo[1], x);
            } else {
                lo[0] = max_into(lo[0], x);
                hi[1] = min_into(hi[1], x);
            }
        }
        if (!(lo[0] < hi[0]) && !(lo[1] < hi[1])) {
            visited = i + 1;
            return false;
        }
    }
    visited = n;
    for (int k = 0; k < 2; ++k)
        if (lo[k] < hi[k] && std::isfinite(lo[k]) && std::isfinite(hi[k])) {
            const double xo = 0.5 * (lo[k] + hi[k]);
            o = m + ((xo - Xm) / f.uu) * f.u;
            return in_predicate_domain(o);
        }
    return false;
}

// Corners kept at most by clipped_kernel_point; beyond, it gives up (its work is O(n k) for k
// corners). Kernels where the mean fails are small polygons; a loop close to convex, whose
// kernel has as many corners as the loop, passes with the mean.
inline constexpr int kMaxKernelCorners = 64;
enum class KernelSearch : uint8_t { kFound, kEmpty, kTooManyCorners };

// The clipping's order of the edges: from `start` (the edge where the mean failed the kernel
// test: its line, or edge 0's, cuts the mean off the kernel) in steps of g, the largest g <= 0.618 n
// coprime to n, so that every edge comes once. Why: consecutive edges of a loop each cut the
// polygon a little and add a corner; edges spread around the loop cut it down to near the
// kernel at once, so the polygon keeps fewer corners (each clip costs O(corners)) and an empty
// kernel shows sooner. Measured on the 64K folding sheet (`bench contour`, same nodes tested and
// passed): contour time 0.75x in DCD, 0.91x in CCD, against the loop's own order from edge 0.
inline int32_t clip_stride(int32_t n) {
    auto gcd = [](int64_t a, int64_t b) {
        while (b != 0) {
            const int64_t t = a % b;
            a = b;
            b = t;
        }
        return a;
    };
    int64_t g = static_cast<int64_t>(n) * 618 / 1000;
    while (g > 1 && gcd(g, n) != 1) --g;
    return g < 1 ? 1 : static_cast<int32_t>(g);
}

// The kernel of the loop projected along l (ProjectionFrame coordinates relative to its first
// vertex c): the polygon where every edge (a, b) sees p on its inner side,
// sg cross2(b - a, p - a) > 0, sg the orientation of the projected loop (its signed area). Start
// from the loop's bounding box (the kernel lies in the loop) and clip the convex polygon by one
// edge's line at a time (Sutherland-Hodgman against one half-plane). o = the 3D point that
// projects to the mean of the corners: inside the kernel if the polygon is proper. Rounding
// only moves o; the contour test that follows decides with exact signs whether o works.
// The edges clip in clip_stride's order from edge `start`. `visited`: the edges examined (each
// edge clips once).
inline KernelSearch clipped_kernel_point(const int32_t* loop, int32_t n, const double* V, const ProjectionFrame& f,
                                         ProjectionScratch& s, Vec3& o, int32_t& visited, int32_t start = 0) {
    double* X = scratch_buffer(s.X, static_cast<size_t>(n));
    double* Y = scratch_buffer(s.Y, static_cast<size_t>(n));
    const Vec3 c = load(V, loop[0]);
    double area2 = 0.0, x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;
    X[0] = Y[0] = 0.0;
    for (int32_t i = 1; i < n; ++i) {
        project(load(V, loop[i]), c, f, X[i], Y[i]);
        area2 += X[i - 1] * Y[i] - X[i] * Y[i - 1];  // shoelace about c (the closing term is 0)
        x0 = min_into(x0, X[i]), x1 = max_into(x1, X[i]), y0 = min_into(y0, Y[i]), y1 = max_into(y1, Y[i]);
    }
    visited = 0;
    if (!(area2 != 0.0) || !(x0 < x1) || !(y0 < y1)) return KernelSearch::kEmpty;  // flat, or not finite
    const double sg = area2 > 0 ? 1.0 : -1.0;
    // Two corner buffers, swapped after each clip. A clip adds at most one corner; the buffers
    // hold two per corner, what the branch-free rebuild below may write before it is checked.
    double px[2][2 * kMaxKernelCorners + 2], py[2][2 * kMaxKernelCorners + 2];
    int cur = 0, k = 4;
    px[0][0] = x0, py[0][0] = y0, px[0][1] = x1, py[0][1] = y0, px[0][2] = x1, py[0][2] = y1, px[0][3] = x0, py[0][3] = y1;
    const int32_t g = clip_stride(n);
    int32_t i = start >= 0 && start < n ? start : 0;
    for (int32_t step = 0; step < n; ++step, i = i + g < n ? i + g : i + g - n) {
        visited = step + 1;
        const int32_t j = i + 1 == n ? 0 : i + 1;
        const double ax = X[i], ay = Y[i], ex = X[j] - ax, ey = Y[j] - ay;
        if (ex == 0.0 && ey == 0.0) continue;  // an edge along l: floats do not resolve its line
        const auto side = [&](double x, double y) { return sg * (ex * (y - ay) - ey * (x - ax)); };
        const double *qx = px[cur], *qy = py[cur];
        double sd[2 * kMaxKernelCorners + 2];
        bool inside = true;  // most edges leave the polygon as it is
        for (int a = 0; a < k; ++a) inside &= (sd[a] = side(qx[a], qy[a])) > 0;
        if (inside) continue;
        // Rebuild without data-dependent branches (their signs are unpredictable): every corner
        // edge (b, a) writes its crossing and its end a, and keeps each only if it is one.
        double *rx = px[1 - cur], *ry = py[1 - cur];
        int m = 0;
        double sp = sd[k - 1];
        for (int a = 0, b = k - 1; a < k; b = a++) {
            const double sa = sd[a];
            const double t = sp / (sp - sa);  // kept only where the signs differ (then sp != sa)
            rx[m] = qx[b] + t * (qx[a] - qx[b]), ry[m] = qy[b] + t * (qy[a] - qy[b]);
            m += (sp > 0) != (sa > 0);
            rx[m] = qx[a], ry[m] = qy[a];
            m += sa > 0;
            sp = sa;
        }
        if (m > kMaxKernelCorners) return KernelSearch::kTooManyCorners;
        if (m < 3) return KernelSearch::kEmpty;
        k = m;
        cur = 1 - cur;
    }
    double sx = 0.0, sy = 0.0;
    for (int a = 0; a < k; ++a) sx += px[cur][a], sy += py[cur][a];
    o = c + ((sx / k) / f.uu) * f.u + ((sy / k) / dot(f.w, f.w)) * f.w;
    return in_predicate_domain(o) ? KernelSearch::kFound : KernelSearch::kEmpty;
}

// A kernel point for the loop at V other than its mean m: clipped_kernel_point (from edge
// `start`), or, if the kernel polygon grows too many corners, the line search through m. False
// if neither finds one.
inline bool find_kernel_point(const int32_t* loop, int32_t n, const double* V, const Vec3& l, const Vec3& m,
                              ProjectionScratch& s, Vec3& o, int32_t& visited, int32_t start = 0) {
    const ProjectionFrame f = projection_frame(l);
    const KernelSearch k = clipped_kernel_point(loop, n, V, f, s, o, visited, start);
    if (k != KernelSearch::kTooManyCorners) return k == KernelSearch::kFound;
    double d1;
    int32_t searched = 0;
    const bool found = search_kernel_point(loop, n, V, f, m, s, o, d1, searched);
    visited += searched;
    return found;
}

}  // namespace conecull
