// Predicate bindings (core/include/conecull/predicates/orient.hpp), vectorised over rows.
#include "common.hpp"
#include "conecull/ccd/non_penetration.hpp"
#include "conecull/predicates/orient.hpp"

namespace conecull::bind {

namespace {

template <class Fn>
py::array_t<int8_t> rows4(const F64Array& a, const F64Array& b, const F64Array& c, const F64Array& d,
                          const char* const (&names)[4], Fn fn) {
    require_points(a, names[0], -1, 3);
    const py::ssize_t k = a.shape(0);
    require_points(b, names[1], k, 3);
    require_points(c, names[2], k, 3);
    require_points(d, names[3], k, 3);
    py::array_t<int8_t> out(k);
    for (py::ssize_t i = 0; i < k; ++i) out.mutable_data()[i] = static_cast<int8_t>(fn(row(a, i), row(b, i), row(c, i), row(d, i)));
    return out;
}

// The non-penetration filter on k pairs: eight (k, 3) arrays, the pair's four points at t = 0
// then at t = 1; true per row if the filter culls it.
template <class Fn>
py::array_t<bool> rows8(const F64Array (&x)[8], const char* const (&names)[8], Fn fn) {
    require_points(x[0], names[0], -1, 3);
    const py::ssize_t k = x[0].shape(0);
    for (int j = 1; j < 8; ++j) require_points(x[j], names[j], k, 3);
    py::array_t<bool> out(k);
    for (py::ssize_t i = 0; i < k; ++i)
        out.mutable_data()[i] = fn(row(x[0], i), row(x[1], i), row(x[2], i), row(x[3], i), row(x[4], i), row(x[5], i),
                                   row(x[6], i), row(x[7], i));
    return out;
}

// The CCD loop's four-at-a-time filter on rows of `pairs` (VF: vertex, face; EE: edge, edge), in
// blocks of four as the loop runs them (the last block padded with its first pair): per row 1 if
// proven culled, -1 if proven kept, 0 if left to the exact filter.
template <class Four>
py::array_t<int8_t> never_coplanar_blocks(const F64Array& V0, const F64Array& V1, const I32Array& prims, int cols,
                                        const char* prims_name, const I32Array& pairs, bool vf, Four four) {
    require_points(V0, "V0", -1, 3);
    require_points(V1, "V1", V0.shape(0), 3);
    require_shape(prims, prims_name, -1, cols);
    require_indices(prims, prims_name, "vertex index", V0.shape(0));
    require_shape(pairs, "pairs", -1, 2);
    const py::ssize_t k = pairs.shape(0);
    const int32_t* q = pairs.data();
    for (py::ssize_t i = 0; i < k; ++i) {
        const int64_t n0 = vf ? V0.shape(0) : prims.shape(0), n1 = prims.shape(0);
        if (q[2 * i] < 0 || q[2 * i] >= n0 || q[2 * i + 1] < 0 || q[2 * i + 1] >= n1)
            throw py::value_error("pairs: row " + std::to_string(i) + " (" + std::to_string(q[2 * i]) + ", " +
                                  std::to_string(q[2 * i + 1]) + ") is outside [0, " + std::to_string(n0) + ") x [0, " +
                                  std::to_string(n1) + ")");
    }
    py::array_t<int8_t> out(k);
    int8_t* o = out.mutable_data();
    for (py::ssize_t b = 0; b < k; b += 4) {
        uint64_t keys[4];
        for (int l = 0; l < 4; ++l) {
            const py::ssize_t i = b + l < k ? b + l : b;
            keys[l] = static_cast<uint64_t>(q[2 * i]) << 32 | static_cast<uint32_t>(q[2 * i + 1]);
        }
        const uint32_t bits = four(V0.data(), V1.data(), prims.data(), keys);
        for (int l = 0; l < 4 && b + l < k; ++l) o[b + l] = (bits >> l & 1) ? 1 : (bits >> (4 + l) & 1) ? -1 : 0;
    }
    return out;
}

}  // namespace

void bind_predicates(py::module_& m) {
    m.def("orient3d", [](const F64Array& a, const F64Array& b, const F64Array& c, const F64Array& d) {
        return rows4(a, b, c, d, {"a", "b", "c", "d"}, [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return orient3d(a, b, c, d); });
    }, py::arg("a"), py::arg("b"), py::arg("c"), py::arg("d"), "sign(((b - a) x (c - a)) . (d - a)) per row.");
    m.def("side_sign", [](const F64Array& a, const F64Array& b, const F64Array& c, const F64Array& l) {
        return rows4(a, b, c, l, {"a", "b", "c", "l"}, [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& l) { return side_sign(a, b, c, l); });
    }, py::arg("a"), py::arg("b"), py::arg("c"), py::arg("l"), "SideSign(a, b, c, l) = sign(((a - c) x (b - c)) . l) per row.");
    m.def("ray_side_sign", [](const F64Array& v, const F64Array& o, const F64Array& r, const F64Array& l) {
        return rows4(v, o, r, l, {"v", "o", "r", "l"}, [](const Vec3& v, const Vec3& o, const Vec3& r, const Vec3& l) { return ray_side_sign(v, o, r, l); });
    }, py::arg("v"), py::arg("o"), py::arg("r"), py::arg("l"), "SideSign(v, o, o + r, l) without rounding o + r per row.");
    m.def("orient2d", [](const F64Array& a, const F64Array& b, const F64Array& c) {
        require_points(a, "a", -1, 2);
        const py::ssize_t k = a.shape(0);
        require_points(b, "b", k, 2);
        require_points(c, "c", k, 2);
        py::array_t<int8_t> out(k);
        for (py::ssize_t i = 0; i < k; ++i) {
            const double* p = a.data() + 2 * i; const double* q = b.data() + 2 * i; const double* s = c.data() + 2 * i;
            out.mutable_data()[i] = static_cast<int8_t>(orient2d(p[0], p[1], q[0], q[1], s[0], s[1]));
        }
        return out;
    }, py::arg("a"), py::arg("b"), py::arg("c"), "sign((b - a) x (c - a)) per row of (k, 2) arrays.");
    m.def("vf_never_coplanar", [](const F64Array& v0, const F64Array& a0, const F64Array& b0, const F64Array& c0,
                                  const F64Array& v1, const F64Array& a1, const F64Array& b1, const F64Array& c1) {
        return rows8({v0, a0, b0, c0, v1, a1, b1, c1}, {"v0", "a0", "b0", "c0", "v1", "a1", "b1", "c1"},
                     [](auto... p) { return vf_never_coplanar(p...); });
    }, py::arg("v0"), py::arg("a0"), py::arg("b0"), py::arg("c0"), py::arg("v1"), py::arg("a1"), py::arg("b1"), py::arg("c1"),
       "Non-penetration filter (ccd/non_penetration.hpp) per row: True if vertex v and triangle (a, b, c), moving "
       "linearly from the *0 to the *1 positions, are proven never coplanar for t in [0, 1] (exact).");
    m.def("ee_never_coplanar", [](const F64Array& a0, const F64Array& b0, const F64Array& c0, const F64Array& d0,
                                  const F64Array& a1, const F64Array& b1, const F64Array& c1, const F64Array& d1) {
        return rows8({a0, b0, c0, d0, a1, b1, c1, d1}, {"a0", "b0", "c0", "d0", "a1", "b1", "c1", "d1"},
                     [](auto... p) { return ee_never_coplanar(p...); });
    }, py::arg("a0"), py::arg("b0"), py::arg("c0"), py::arg("d0"), py::arg("a1"), py::arg("b1"), py::arg("c1"), py::arg("d1"),
       "Non-penetration filter per row: True if edges (a, b) and (c, d), moving linearly, are proven never coplanar "
       "for t in [0, 1] (exact).");
    m.def("vf_never_coplanar4", [](const F64Array& V0, const F64Array& V1, const I32Array& faces,
                                   const I32Array& pairs, bool portable) {
        return never_coplanar_blocks(V0, V1, faces, 3, "faces", pairs, true,
                                     portable ? vf_never_coplanar4_portable : vf_never_coplanar4);
    }, py::arg("V0"), py::arg("V1"), py::arg("faces"), py::arg("pairs"), py::arg("portable") = false,
       "The exact CCD loop's floating-point non-penetration filter, four (vertex, face) pairs at a time, per pair: "
       "1 if proven never coplanar (culled), -1 if two coefficients are proven of opposite signs (kept), 0 if "
       "left to the exact filter. portable=True: the path without AVX2.");
    m.def("ee_never_coplanar4", [](const F64Array& V0, const F64Array& V1, const I32Array& edges,
                                   const I32Array& pairs, bool portable) {
        return never_coplanar_blocks(V0, V1, edges, 2, "edges", pairs, false,
                                     portable ? ee_never_coplanar4_portable : ee_never_coplanar4);
    }, py::arg("V0"), py::arg("V1"), py::arg("edges"), py::arg("pairs"), py::arg("portable") = false,
       "As vf_never_coplanar4 on (edge, edge) pairs (rows of edges).");
    m.def("never_coplanar4_vectorised", &never_coplanar4_vectorised,
          "Whether vf_never_coplanar4 / ee_never_coplanar4 run their AVX2 path on this CPU.");
}

}  // namespace conecull::bind
