// Binding helpers: convert and validate only. Shape errors name the argument and its shape.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "conecull/parallel.hpp"
#include "conecull/vec3.hpp"

namespace py = pybind11;

namespace conecull::bind {

// A thread count's cap: it only stops a typo from starting thousands of threads.
constexpr int kMaxThreads = 1024;

// Runs f() with the GIL released. Not py::gil_scoped_release: its destructor takes the GIL back,
// and a daemon thread that does so while the interpreter shuts down is ended right there by
// pthread_exit, whose unwinding out of a destructor (noexcept) aborts the whole process
// ("terminate called without an active exception"; measured: 5 of 5 runs of a script whose
// daemon thread was querying when it ended). From a plain call it unwinds like any thread exit.
template <class F>
void without_gil(F&& f) {
    PyThreadState* state = PyEval_SaveThread();
    std::exception_ptr error;
    try {
        f();
    } catch (...) {
        error = std::current_exception();
    }
    PyEval_RestoreThread(state);
    if (error) std::rethrow_exception(error);
}

using F64Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using I32Array = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

inline std::string shape_str(const py::array& a) {
    std::ostringstream s;
    s << "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
    s << (a.ndim() == 1 ? ",)" : ")");
    return s.str();
}

// Raises ValueError unless `a` has shape (rows, cols); rows < 0 means any.
inline void require_shape(const py::array& a, const char* name, py::ssize_t rows, py::ssize_t cols) {
    if (a.ndim() != 2 || a.shape(1) != cols || (rows >= 0 && a.shape(0) != rows)) {
        std::ostringstream s;
        s << name << ": expected shape (" << (rows >= 0 ? std::to_string(rows) : std::string("k")) << ", " << cols
          << "), got " << shape_str(a);
        throw py::value_error(s.str());
    }
}

// Raises ValueError naming the argument unless every entry of `a` lies in [0, n); `what` says
// what an entry is ("vertex index").
inline void require_indices(const I32Array& a, const char* name, const char* what, int64_t n) {
    const int32_t* v = a.data();
    for (py::ssize_t i = 0; i < a.size(); ++i)
        if (v[i] < 0 || v[i] >= n)
            throw py::value_error(std::string(name) + ": " + what + " " + std::to_string(v[i]) + " outside [0, " +
                                  std::to_string(n) + ")");
}

// A double as Python's repr() writes it (nan, inf, shortest round trip), for messages.
inline std::string repr(double x) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

// 1 unless x is 0 or finite with |x| in [2^-128, 2^128]. On |x|'s bits: non-negative doubles
// order as their bit patterns, and infinities and NaNs lie above 2^128's. |x| is in
// [2^-128, 2^128) iff its high 32-bit word is in [0x37f00000, 0x47f00000) (both ends' low words
// are 0); 2^128 itself is the one pattern with high word 0x47f00000 allowed. In 32-bit words,
// with an unsigned int (not a bool) to accumulate, GCC vectorises the scan with SSE2, which
// has no 64-bit compare: 0.35 ns per value against 0.8 for one 64-bit comparison (measured on
// 96K values, a 32K-vertex query's positions).
inline uint32_t out_of_coordinate_range(double x) {
    uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    const uint32_t hi = static_cast<uint32_t>(b >> 32) & 0x7fffffffu, lo = static_cast<uint32_t>(b);
    return !(((hi | lo) == 0) | (hi - 0x37f00000u < 0x10000000u) | ((hi == 0x47f00000u) & (lo == 0)));
}

// 1 if any of v[b, e) is out of the coordinate range (out_of_coordinate_range, vectorised).
inline uint32_t any_out_of_coordinate_range(const double* v, int64_t b, int64_t e) {
    uint32_t out = 0;
    for (int64_t i = b; i < e; ++i) out |= out_of_coordinate_range(v[i]);
    return out;
}

// Raises ValueError, naming the argument and the entry (row and column of a 2D array), unless
// every value of `a` is finite and, if not zero, of magnitude in [2^-128, 2^128]: the range in
// which the exact predicates cannot overflow or underflow (the same rule and messages as
// the public API, which leaves the check to this one). With threads > 1 (a query's, parallel.hpp)
// the scan runs in chunks of 16K values on them; the first value out of range is then found
// serially. Why: a query's positions are mostly not in cache when it starts (the previous query
// read other arrays), and the scan of a 32K-vertex sheet's 96K values took ~0.09 ms of a 3.4 ms
// one-thread DCD query (2.6% of its samples in a perf profile), serial work a second thread halves.
inline void require_coordinates(const F64Array& a, const char* name, int threads = 1) {
    const double* v = a.data();
    const int64_t n = a.size();
    constexpr int64_t kChunk = 1 << 14;
    const int64_t chunks = (n + kChunk - 1) / kChunk;
    if (threads <= 1 || chunks < 2) {
        if (!any_out_of_coordinate_range(v, 0, n)) return;
    } else {
        std::atomic<uint32_t> out{0};
        parallel_chunks(chunks, threads, [&](int64_t c, int) {
            if (any_out_of_coordinate_range(v, c * kChunk, std::min(n, (c + 1) * kChunk)))
                out.store(1, std::memory_order_relaxed);
        });
        if (!out.load(std::memory_order_relaxed)) return;
    }
    int64_t bad = 0;
    while (!out_of_coordinate_range(v[bad])) ++bad;
    std::string where;
    if (a.ndim() == 2) {
        where = " at row " + std::to_string(bad / a.shape(1)) + ", column " + std::to_string(bad % a.shape(1));
    } else {  // the index as a tuple (C order), or one number for a 1-D array
        std::vector<py::ssize_t> idx(a.ndim());
        for (py::ssize_t d = a.ndim() - 1, r = bad; d >= 0; --d) idx[d] = r % a.shape(d), r /= a.shape(d);
        for (size_t d = 0; d < idx.size(); ++d) where += (d ? ", " : "") + std::to_string(idx[d]);
        where = " at index " + (idx.size() == 1 ? where : "(" + where + ")");
    }
    const double x = v[bad];
    if (!std::isfinite(x)) throw py::value_error(std::string(name) + ": non-finite coordinate " + repr(x) + where);
    throw py::value_error(std::string(name) + ": coordinate " + repr(x) + where +
                          " is outside the supported range: non-zero magnitudes must lie in [2^-128, 2^128] for the "
                          "predicates to stay exact (rescale the mesh)");
}

// require_shape, then require_coordinates (on `threads`): positions (or directions) entering the
// predicates.
inline void require_points(const F64Array& a, const char* name, py::ssize_t rows, py::ssize_t cols, int threads = 1) {
    require_shape(a, name, rows, cols);
    require_coordinates(a, name, threads);
}

// Raises ValueError naming the argument unless every value of `a` is finite (cone bounds).
inline void require_finite(const F64Array& a, const char* name) {
    for (py::ssize_t i = 0; i < a.size(); ++i)
        if (!std::isfinite(a.data()[i]))
            throw py::value_error(std::string(name) + ": non-finite value " + repr(a.data()[i]) + " at index " +
                                  std::to_string(i));
}

template <class T>
py::array_t<T> to_numpy(const std::vector<T>& v) {
    py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

template <class T>
py::array_t<T> to_numpy(const std::vector<T>& v, py::ssize_t cols) {
    py::array_t<T> a({static_cast<py::ssize_t>(v.size()) / cols, cols});
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

// A (3,) vector argument (an axis, a ray, a kernel point); ValueError naming it if mis-shaped
// or out of the coordinate range.
inline Vec3 vec3_arg(const F64Array& a, const char* name) {
    if (a.ndim() != 1 || a.shape(0) != 3)
        throw py::value_error(std::string(name) + ": expected shape (3,), got " + shape_str(a));
    require_coordinates(a, name);
    return Vec3{a.data()[0], a.data()[1], a.data()[2]};
}

// The same for an optional one.
inline std::optional<Vec3> opt_vec3(const std::optional<F64Array>& a, const char* name) {
    if (!a) return std::nullopt;
    return vec3_arg(*a, name);
}

// (k, 3) float64 rows -> Vec3.
inline Vec3 row(const F64Array& a, py::ssize_t i) {
    const double* p = a.data() + 3 * i;
    return {p[0], p[1], p[2]};
}

}  // namespace conecull::bind
