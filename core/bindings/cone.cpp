// Normal cone bindings (core/include/conecull/cone/normal_cone.hpp), vectorised over rows.
#include "stages.hpp"

namespace conecull::bind {

py::dict cone_arrays(const std::vector<NormalCone>& cones) {
    const py::ssize_t n = static_cast<py::ssize_t>(cones.size());
    py::array_t<double> axis({n, py::ssize_t(3)}), cos_bound(n), sin_bound(n);
    for (py::ssize_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) axis.mutable_data()[3 * i + k] = cones[i].axis[k];
        cos_bound.mutable_data()[i] = cones[i].cos_bound;
        sin_bound.mutable_data()[i] = cones[i].sin_bound;
    }
    py::dict d;
    d["axis"] = axis;
    d["cos_bound"] = cos_bound;
    d["sin_bound"] = sin_bound;
    return d;
}

namespace {

// A bounded cone (cos > 0) as the merge's rounding analysis assumes it (kConeSlack): a unit axis
// (up to 16 kEps, the core's own are within 5) and bounds some half-angle can meet, cos <= 1 and
// sin >= 0. Anything else would merge into a cone that bounds nothing, silently. A full cone's
// axis and sine are never read.
void require_bounded_cones(const F64Array& axis, const F64Array& cos_b, const F64Array& sin_b, const char* which) {
    const std::string w(which);
    for (py::ssize_t i = 0; i < axis.shape(0); ++i) {
        const double c = cos_b.data()[i], s = sin_b.data()[i];
        if (!(c > 0.0)) continue;
        const double len = norm(row(axis, i));
        if (!(std::fabs(len - 1.0) <= 16.0 * kEps))
            throw py::value_error("axis_" + w + ": row " + std::to_string(i) + " has length " + repr(len) +
                                  "; a bounded cone (cos_" + w + " > 0) needs a unit axis");
        if (c > 1.0)
            throw py::value_error("cos_" + w + ": " + repr(c) + " at index " + std::to_string(i) + " is above 1");
        if (s < 0.0)
            throw py::value_error("sin_" + w + ": " + repr(s) + " at index " + std::to_string(i) +
                                  " is negative (a bound on the sine of a half-angle in [0, pi/2))");
    }
}

py::tuple split(const std::vector<NormalCone>& cones) {
    const py::dict d = cone_arrays(cones);
    return py::make_tuple(d["axis"], d["cos_bound"], d["sin_bound"]);
}

}  // namespace

void bind_cone(py::module_& m) {
    m.def(
        "triangle_cone",
        [](const F64Array& a, const F64Array& b, const F64Array& c) {
            require_points(a, "a", -1, 3);
            require_points(b, "b", a.shape(0), 3);
            require_points(c, "c", a.shape(0), 3);
            std::vector<NormalCone> out(a.shape(0));
            for (py::ssize_t i = 0; i < a.shape(0); ++i) out[i] = triangle_cone(row(a, i), row(b, i), row(c, i));
            return split(out);
        },
        py::arg("a"), py::arg("b"), py::arg("c"),
        "Cones of triangles (a, b, c), each (k, 3): returns (axis (k, 3), cos_bound (k,), sin_bound (k,)).");
    m.def(
        "merge_cones",
        [](const F64Array& axis_p, const F64Array& cos_p, const F64Array& sin_p, const F64Array& axis_q,
           const F64Array& cos_q, const F64Array& sin_q) {
            require_shape(axis_p, "axis_p", -1, 3);
            require_shape(axis_q, "axis_q", axis_p.shape(0), 3);
            const py::ssize_t k = axis_p.shape(0);
            for (const F64Array* a : {&cos_p, &sin_p, &cos_q, &sin_q})
                if (a->ndim() != 1 || a->shape(0) != k)
                    throw py::value_error("cos_p, sin_p, cos_q, sin_q: expected shape (" + std::to_string(k) + ",)");
            // Cones are not coordinates (tiny axis components are fine), but must be numbers.
            require_finite(axis_p, "axis_p");
            require_finite(axis_q, "axis_q");
            require_finite(cos_p, "cos_p");
            require_finite(sin_p, "sin_p");
            require_finite(cos_q, "cos_q");
            require_finite(sin_q, "sin_q");
            require_bounded_cones(axis_p, cos_p, sin_p, "p");
            require_bounded_cones(axis_q, cos_q, sin_q, "q");
            std::vector<NormalCone> out(k);
            for (py::ssize_t i = 0; i < k; ++i) {
                NormalCone p{row(axis_p, i), cos_p.data()[i], sin_p.data()[i]};
                NormalCone q{row(axis_q, i), cos_q.data()[i], sin_q.data()[i]};
                out[i] = merge(p, q);
            }
            return split(out);
        },
        py::arg("axis_p"), py::arg("cos_p"), py::arg("sin_p"), py::arg("axis_q"), py::arg("cos_q"), py::arg("sin_q"),
        "Merge cones row by row: returns (axis, cos_bound, sin_bound). A bounded cone (cos > 0) needs a unit "
        "axis, cos <= 1 and sin >= 0 (ValueError otherwise); a full cone's axis and sine are not read.");
}

}  // namespace conecull::bind
