// Contour bindings (core/include/conecull/contour/): per-node loops and Alg. 1 on one loop.
#include <limits>
#include <optional>

#include <pybind11/stl.h>

#include "conecull/contour/contour_test.hpp"
#include "conecull/contour/contour_test_cbc.hpp"
#include "conecull/contour/contour_test_sct.hpp"
#include "conecull/contour/contour_test_simple.hpp"
#include "conecull/traversal/self_collide.hpp"
#include "stages.hpp"

namespace conecull::bind {

py::dict contour_arrays(const Contours& c) {
    py::dict d;
    d["status"] = to_numpy(c.status);
    d["offsets"] = to_numpy(c.offsets);
    d["vertices"] = to_numpy(c.vertices);
    d["components"] = to_numpy(c.components);
    return d;
}

py::dict verdict_dict(const ContourVerdict& v) {
    py::dict d;
    d["passed"] = v.passed();
    d["reason"] = static_cast<int>(v.reason);
    d["edge"] = v.edge;
    d["crossings"] = v.crossings;
    d["kernel"] = py::make_tuple(v.kernel.x, v.kernel.y, v.kernel.z);
    d["kernel_end"] = py::make_tuple(v.kernel_end.x, v.kernel_end.y, v.kernel_end.z);
    d["ray"] = py::make_tuple(v.ray.x, v.ray.y, v.ray.z);
    d["other_edge"] = v.other_edge;
    d["edges_visited"] = v.edges_visited;
    d["simple"] = v.by_simplicity;
    return d;
}

// A loop of vertex ids into positions with n_vertices rows, and its axis l (3,).
static Vec3 check_loop_axis(const I32Array& loop, py::ssize_t n_vertices, const F64Array& l) {
    if (loop.ndim() != 1 || loop.shape(0) < 3) throw py::value_error("loop: expected shape (n,) with n >= 3");
    const Vec3 axis = vec3_arg(l, "l");
    for (py::ssize_t i = 0; i < loop.shape(0); ++i)
        if (loop.data()[i] < 0 || loop.data()[i] >= n_vertices) throw py::value_error("loop: index out of range");
    return axis;
}

Vec3 check_loop_pose(const I32Array& loop, const F64Array& V, const F64Array& l) {
    require_points(V, "V", -1, 3);
    return check_loop_axis(loop, V.shape(0), l);
}

Vec3 check_loop_step(const I32Array& loop, const F64Array& V0, const F64Array& V1, const F64Array& l) {
    require_points(V0, "V0", -1, 3);
    require_points(V1, "V1", V0.shape(0), 3);
    return check_loop_axis(loop, V0.shape(0), l);
}

void bind_contour(py::module_& m) {
    m.def(
        "contour_test",
        [](const I32Array& loop, const F64Array& V, const F64Array& l, std::optional<F64Array> r,
           std::optional<F64Array> o) {
            const Vec3 axis = check_loop_pose(loop, V, l);
            const int32_t n = static_cast<int32_t>(loop.shape(0));
            return verdict_dict(contour_test_choosing(
                axis, opt_vec3(r, "r"), opt_vec3(o, "o"), [&] { return kernel_point(loop.data(), n, V.data()); },
                [&](const Vec3& d, const Vec3& k) {
                    return unprojected_contour_test_with_ray(loop.data(), n, V.data(), axis, d, k);
                },
                [&] { return unprojected_contour_test(loop.data(), n, V.data(), axis); }));
        },
        py::arg("loop"), py::arg("V"), py::arg("l"), py::arg("r") = py::none(), py::arg("o") = py::none(),
        "Alg. 1 on the loop of vertex ids `loop` with positions V (n, 3) and axis l (3,). By default the core's\n"
        "choices: o the mean, then a point inside the loop's kernel (the polygon clipped from its edges'\n"
        "half-planes) if the mean fails the kernel test; generic ray\n"
        "directions, a second one if the first hits a vertex. o (3,) fixes the kernel point, r (3,) the ray\n"
        "(with r alone, o is the mean).");
    m.def(
        "sct_contour_test",
        [](const I32Array& loop, const F64Array& V, const F64Array& l) {
            const Vec3 axis = check_loop_pose(loop, V, l);
            ProjectionScratch scratch;
            return verdict_dict(
                projected_contour_test(loop.data(), static_cast<int32_t>(loop.shape(0)), V.data(), axis, scratch));
        },
        py::arg("loop"), py::arg("V"), py::arg("l"),
        "The \"sct\" baseline's projected star-contour test [SPO10] on one loop (certified).");
    m.def(
        "cbc_contour_test",
        [](const I32Array& loop, const F64Array& V, const F64Array& l) {
            const Vec3 axis = check_loop_pose(loop, V, l);
            return verdict_dict(quadratic_contour_test(loop.data(), static_cast<int32_t>(loop.shape(0)), V.data(), axis));
        },
        py::arg("loop"), py::arg("V"), py::arg("l"),
        "The \"cbc\" baseline's O(n^2) edge-pair contour test [TCYM09] at one pose (certified).");
    m.def(
        "simplicity_test",
        [](const I32Array& loop, const F64Array& V, const F64Array& l) {
            const Vec3 axis = check_loop_pose(loop, V, l);
            SimplicityScratch scratch;
            const int32_t n = static_cast<int32_t>(loop.shape(0));
            ContourVerdict v = simplicity_test(loop.data(), n, V.data(), axis, scratch);
            v.kernel = v.kernel_end = kernel_point(loop.data(), n, V.data());  // reported only, as cbc's
            return verdict_dict(v);
        },
        py::arg("loop"), py::arg("V"), py::arg("l"),
        "The simplicity fallback of \"nc\" (DCD): is the loop projected along l a simple polygon? The edge-pair\n"
        "predicates of the cbc test, on the pairs whose extents overlap along both sweep axes (certified).");
    m.def(
        "simplicity_pass",
        [](const I32Array& loop, const F64Array& V, const F64Array& l, bool portable) {
            const Vec3 axis = check_loop_pose(loop, V, l);
            const int32_t n = static_cast<int32_t>(loop.shape(0));
            // NaN first: an entry the pass fails to write shows (the traversal's buffers hold an
            // earlier loop's numbers).
            std::vector<double> zg(static_cast<size_t>(n) + 2, std::numeric_limits<double>::quiet_NaN()), zh(zg);
            const Vec3 c = load(V.data(), loop.data()[0]);
            const ProjectionFrame f = projection_frame(axis);
            double d1, margin;
            if (portable) {
                d1 = project_loop_gh_portable(loop.data(), V.data(), n, c, f, zg.data(), zh.data());
                margin = least_turn_margin_portable(zg.data(), zh.data(), n);
            } else {
                d1 = project_loop_gh(loop.data(), V.data(), n, c, f, zg.data(), zh.data());
                margin = least_turn_margin(zg.data(), zh.data(), n);
            }
            return py::make_tuple(to_numpy(zg), to_numpy(zh), d1, margin);
        },
        py::arg("loop"), py::arg("V"), py::arg("l"), py::arg("portable") = false,
        "The simplicity test's one-pose pass: (zg, zh, d1, margin), Z_g and Z_h of the loop's vertices (two\n"
        "wrapped at the end), the largest |p - c|_1 and the least turn margin (+0 for a zero). portable=True: the\n"
        "path without AVX2 (the same numbers, bit for bit).");
    m.def("simplicity_pass_vectorised", &simplicity_pass_vectorised,
          "Whether the simplicity test's one-pose pass runs its AVX2 path on this CPU.");
    m.def(
        "simplicity_test_ccd",
        [](const I32Array& loop, const F64Array& V0, const F64Array& V1, const F64Array& l) {
            const Vec3 axis = check_loop_step(loop, V0, V1, l);
            SimplicityScratch scratch;
            const int32_t n = static_cast<int32_t>(loop.shape(0));
            ContourVerdict v = simplicity_test_ccd(loop.data(), n, V0.data(), V1.data(), axis, scratch);
            v.kernel = kernel_point(loop.data(), n, V0.data());  // reported only, as cbc's
            v.kernel_end = kernel_point(loop.data(), n, V1.data());
            return verdict_dict(v);
        },
        py::arg("loop"), py::arg("V0"), py::arg("V1"), py::arg("l"),
        "The simplicity fallback of \"nc\" over the step V0 -> V1: is the loop projected along l simple at\n"
        "every t? The cbc test's continuous edge-pair predicates, on the pairs whose extents over the step\n"
        "overlap (certified).");
    m.def(
        "nc_contour_test",
        [](const I32Array& loop, const F64Array& V, const F64Array& l, bool simplicity_first) {
            const Vec3 axis = check_loop_pose(loop, V, l);
            FirstTest first = simplicity_first ? FirstTest::kSimplicity : FirstTest::kStar;
            return verdict_dict(
                Discrete{V.data(), &first}.contour_test(0, loop.data(), static_cast<int32_t>(loop.shape(0)), axis));
        },
        py::arg("loop"), py::arg("V"), py::arg("l"), py::arg("simplicity_first") = false,
        "The contour test \"nc\" runs in its traversal (DCD): Alg. 1 with the mean, then the simplicity\n"
        "test, then the kernel-point search where the simplicity test gave up; with simplicity_first, the\n"
        "simplicity test first (as the traversal does on a node it proved when last tested), then\n"
        "Alg. 1. \"simple\": passed by the simplicity test (no kernel point, NaN, if it ran first).");
    m.def(
        "nc_contour_test_ccd",
        [](const I32Array& loop, const F64Array& V0, const F64Array& V1, const F64Array& l, bool simplicity_first) {
            const Vec3 axis = check_loop_step(loop, V0, V1, l);
            FirstTest first = simplicity_first ? FirstTest::kSimplicity : FirstTest::kStar;
            return verdict_dict(Continuous{V0.data(), V1.data(), &first}.contour_test(
                0, loop.data(), static_cast<int32_t>(loop.shape(0)), axis));
        },
        py::arg("loop"), py::arg("V0"), py::arg("V1"), py::arg("l"), py::arg("simplicity_first") = false,
        "The contour test \"nc\" runs in its traversal over the step V0 -> V1 (CCD): Alg. 3 with the means, the\n"
        "simplicity test, then the kernel-point search wherever the simplicity test failed; with\n"
        "simplicity_first, the simplicity test first, then Alg. 3 and the search.");
    m.def(
        "cbc_contour_test_ccd",
        [](const I32Array& loop, const F64Array& V0, const F64Array& V1, const F64Array& l) {
            const Vec3 axis = check_loop_step(loop, V0, V1, l);
            return verdict_dict(quadratic_contour_test_ccd(loop.data(), static_cast<int32_t>(loop.shape(0)), V0.data(),
                                                           V1.data(), axis));
        },
        py::arg("loop"), py::arg("V0"), py::arg("V1"), py::arg("l"),
        "The \"cbc\" baseline's O(n^2) edge-pair contour test [TCYM09] over the step V0 -> V1 (certified).");
}

}  // namespace conecull::bind
