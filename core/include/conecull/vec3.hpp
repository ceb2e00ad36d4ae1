// A plain 3-vector of doubles; positions cross from NumPy as (n, 3) float64 rows.
#pragma once

#include <cmath>

namespace conecull {

struct Vec3 {
    double x = 0.0, y = 0.0, z = 0.0;
    double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline bool operator==(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

inline Vec3 load(const double* V, int i) { return {V[3 * i], V[3 * i + 1], V[3 * i + 2]}; }

// std::fmin(acc, x) / std::fmax(acc, x) for an accumulator acc that is never NaN: a NaN x leaves
// acc as fmin does. Inline: without -ffinite-math-only std::fmin is a libm call, and these run
// once per contour edge.
inline double min_into(double acc, double x) { return x < acc ? x : acc; }
inline double max_into(double acc, double x) { return x > acc ? x : acc; }

}  // namespace conecull
