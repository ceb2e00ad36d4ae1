// CCD bindings (core/include/conecull/ccd/): cones and Alg. 3, vectorised over rows (tests).
#include <optional>

#include <pybind11/stl.h>

#include "stages.hpp"
#include "conecull/ccd/ccd_cone.hpp"
#include "conecull/ccd/contour_test_ccd.hpp"
#include "conecull/ccd/elementary_ccd.hpp"
#include "conecull/ccd/interval_filter.hpp"

namespace conecull::bind {

namespace {

Arithmetic parse_arithmetic(const std::string& s) {
    if (s == "float") return Arithmetic::kFloat;
    if (s == "conservative") return Arithmetic::kConservative;
    if (s == "exact") return Arithmetic::kExact;
    throw py::value_error("arithmetic: expected 'float', 'conservative' or 'exact', got '" + s + "'");
}

template <class Fn>
py::array_t<bool> rows8(const F64Array (&x)[8], const char* const (&names)[8], Fn fn) {
    require_points(x[0], names[0], -1, 3);
    const py::ssize_t k = x[0].shape(0);
    for (int i = 1; i < 8; ++i) require_points(x[i], names[i], k, 3);
    py::array_t<bool> out(k);
    bool* o = out.mutable_data();  // taken with the GIL held
    without_gil([&] {
        for (py::ssize_t i = 0; i < k; ++i)
            o[i] = fn(row(x[0], i), row(x[1], i), row(x[2], i), row(x[3], i), row(x[4], i), row(x[5], i), row(x[6], i),
                      row(x[7], i));
    });
    return out;
}

}  // namespace

void bind_ccd(py::module_& m) {
    m.def(
        "vertex_face_ccd_rows",
        [](const F64Array& v_t0, const F64Array& f0_t0, const F64Array& f1_t0, const F64Array& f2_t0,
           const F64Array& v_t1, const F64Array& f0_t1, const F64Array& f1_t1, const F64Array& f2_t1,
           const std::string& arithmetic) {
            const Arithmetic mode = parse_arithmetic(arithmetic);
            const F64Array x[8] = {v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1};
            static const char* const names[8] = {"v_t0", "f0_t0", "f1_t0", "f2_t0", "v_t1", "f0_t1", "f1_t1", "f2_t1"};
            return rows8(x, names, [mode](auto... p) { return vertex_face_ccd(p..., mode); });
        },
        py::arg("v_t0"), py::arg("f0_t0"), py::arg("f1_t0"), py::arg("f2_t0"), py::arg("v_t1"), py::arg("f0_t1"),
        py::arg("f1_t1"), py::arg("f2_t1"), py::arg("arithmetic"),
        "Vertex-face CCD per row ((k, 3) arrays): contact at some t in [0, 1].");
    m.def(
        "edge_edge_ccd_rows",
        [](const F64Array& ea0_t0, const F64Array& ea1_t0, const F64Array& eb0_t0, const F64Array& eb1_t0,
           const F64Array& ea0_t1, const F64Array& ea1_t1, const F64Array& eb0_t1, const F64Array& eb1_t1,
           const std::string& arithmetic) {
            const Arithmetic mode = parse_arithmetic(arithmetic);
            const F64Array x[8] = {ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1};
            static const char* const names[8] = {"ea0_t0", "ea1_t0", "eb0_t0", "eb1_t0", "ea0_t1", "ea1_t1", "eb0_t1", "eb1_t1"};
            return rows8(x, names, [mode](auto... p) { return edge_edge_ccd(p..., mode); });
        },
        py::arg("ea0_t0"), py::arg("ea1_t0"), py::arg("eb0_t0"), py::arg("eb1_t0"), py::arg("ea0_t1"), py::arg("ea1_t1"),
        py::arg("eb0_t1"), py::arg("eb1_t1"), py::arg("arithmetic"),
        "Edge-edge CCD per row ((k, 3) arrays): contact at some t in [0, 1].");
    m.def(
        "time_axis_enclosures",
        [](const std::string& kind, const F64Array& points) {
            if (kind != "vf" && kind != "ee") throw py::value_error("kind: expected 'vf' or 'ee', got '" + kind + "'");
            require_points(points, "points", 8, 3);
            Vec3 x[8];
            for (int i = 0; i < 8; ++i) x[i] = row(points, i);
            const py::ssize_t n = kind == "vf" ? 4 + 5 * 9 : 4 + 5 * 6;
            py::array_t<double> lo(n), hi(n);
            time_axis_enclosures(kind == "vf", x, lo.mutable_data(), hi.mutable_data());
            return py::make_tuple(lo, hi);
        },
        py::arg("kind"), py::arg("points"),
        "The Bernstein enclosures on [0, 1] that exact CCD's time-axis test starts from (interval_filter.hpp): "
        "(lo, hi), f's 4 coefficients then each condition's 5. points: (8, 3), the test's arguments in order.");
    m.def(
        "triangle_cone_ccd",
        [](const F64Array& a0, const F64Array& b0, const F64Array& c0, const F64Array& a1, const F64Array& b1,
           const F64Array& c1) {
            require_points(a0, "a0", -1, 3);
            const py::ssize_t k = a0.shape(0);
            for (const auto& [arr, name] : {std::pair<const F64Array*, const char*>{&b0, "b0"}, {&c0, "c0"}, {&a1, "a1"}, {&b1, "b1"}, {&c1, "c1"}})
                require_points(*arr, name, k, 3);
            py::array_t<double> axis({k, py::ssize_t(3)}), cb(k), sb(k);
            for (py::ssize_t i = 0; i < k; ++i) {
                const NormalCone c = triangle_cone_ccd(row(a0, i), row(b0, i), row(c0, i), row(a1, i), row(b1, i), row(c1, i));
                for (int j = 0; j < 3; ++j) axis.mutable_data()[3 * i + j] = c.axis[j];
                cb.mutable_data()[i] = c.cos_bound;
                sb.mutable_data()[i] = c.sin_bound;
            }
            return py::make_tuple(axis, cb, sb);
        },
        py::arg("a0"), py::arg("b0"), py::arg("c0"), py::arg("a1"), py::arg("b1"), py::arg("c1"),
        "Cones holding n(t) for t in [0, 1] of moving triangles: (axis, cos_bound, sin_bound).");
    m.def(
        "csidesign1",
        [](const F64Array& o, const F64Array& b0, const F64Array& c0, const F64Array& b1, const F64Array& c1,
           const F64Array& l, std::optional<F64Array> o1) {
            require_points(o, "o", -1, 3);
            const py::ssize_t k = o.shape(0);
            for (const auto& [arr, name] : {std::pair<const F64Array*, const char*>{&b0, "b0"}, {&c0, "c0"}, {&b1, "b1"}, {&c1, "c1"}, {&l, "l"}})
                require_points(*arr, name, k, 3);
            if (o1) require_points(*o1, "o1", k, 3);
            const F64Array& end = o1 ? *o1 : o;
            py::array_t<int8_t> out(k);
            for (py::ssize_t i = 0; i < k; ++i)
                out.mutable_data()[i] = static_cast<int8_t>(
                    csidesign1(row(o, i), row(end, i), row(b0, i), row(c0, i), row(b1, i), row(c1, i), row(l, i)));
            return out;
        },
        py::arg("o"), py::arg("b0"), py::arg("c0"), py::arg("b1"), py::arg("c1"), py::arg("l"), py::arg("o1") = py::none(),
        "CSideSign1 per row: s if the three Bernstein coefficients all have the strict sign s, else 0. The kernel\n"
        "point moves from o to o1 (default: o1 = o, fixed as printed).");
    m.def(
        "contour_test_ccd",
        [](const I32Array& loop, const F64Array& V0, const F64Array& V1, const F64Array& l, std::optional<F64Array> r,
           std::optional<F64Array> o, std::optional<F64Array> o1) {
            const Vec3 axis = check_loop_step(loop, V0, V1, l);
            const int32_t n = static_cast<int32_t>(loop.shape(0));
            const std::optional<Vec3> start = opt_vec3(o, "o"), end = opt_vec3(o1, "o1");
            if (end && !start) throw py::value_error("o1: given without o (o1 is where the kernel point o moves to)");
            using Ends = std::pair<Vec3, Vec3>;
            const std::optional<Ends> kernel = start ? std::optional<Ends>(Ends{*start, end ? *end : *start}) : std::nullopt;
            return verdict_dict(contour_test_choosing(
                axis, opt_vec3(r, "r"), kernel,
                [&] { return Ends{kernel_point(loop.data(), n, V0.data()), kernel_point(loop.data(), n, V1.data())}; },
                [&](const Vec3& d, const Ends& k) {
                    return unprojected_contour_test_ccd_with_ray(loop.data(), n, V0.data(), V1.data(), axis, d, k.first,
                                                                 k.second);
                },
                [&] { return unprojected_contour_test_ccd(loop.data(), n, V0.data(), V1.data(), axis); }));
        },
        py::arg("loop"), py::arg("V0"), py::arg("V1"), py::arg("l"), py::arg("r") = py::none(), py::arg("o") = py::none(),
        py::arg("o1") = py::none(),
        "Alg. 3 on the loop `loop` moving from V0 to V1, axis l. The kernel point moves linearly from `kernel`\n"
        "(t = 0) to `kernel_end` (t = 1): by default the mean at t = 0 to the mean at t = 1, then a point in the\n"
        "clipped kernel of the loop at t = 0 to one at t = 1. o fixes it at t = 0 and o1 at t = 1 (default\n"
        "o1 = o: fixed over the step, as printed); r fixes the ray (with r alone, the moving mean).");
}

}  // namespace conecull::bind
