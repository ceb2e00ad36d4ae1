// Binding helpers: convert and validate only. Shape errors name the argument and its shape.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "conecull/vec3.hpp"

namespace py = pybind11;

namespace conecull::bind {

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

// An optional (3,) vector argument (a ray, a kernel point); ValueError naming it if mis-shaped.
inline std::optional<Vec3> opt_vec3(const std::optional<F64Array>& a, const char* name) {
    if (!a) return std::nullopt;
    if (a->ndim() != 1 || a->shape(0) != 3)
        throw py::value_error(std::string(name) + ": expected shape (3,), got " + shape_str(*a));
    return Vec3{a->data()[0], a->data()[1], a->data()[2]};
}

// (k, 3) float64 rows -> Vec3.
inline Vec3 row(const F64Array& a, py::ssize_t i) {
    const double* p = a.data() + 3 * i;
    return {p[0], p[1], p[2]};
}

}  // namespace conecull::bind
