// Elementary test bindings (core/include/conecull/elementary/), vectorised over rows.
#include "common.hpp"
#include "conecull/elementary/triangle_triangle.hpp"
#include "conecull/elementary/triangles_apart.hpp"

namespace conecull::bind {

void bind_elementary(py::module_& m) {
    m.def(
        "triangles_collide",
        [](const I32Array& fp, const F64Array& P, const I32Array& fq, const F64Array& Q) {
            require_shape(fp, "fp", -1, 3);
            const py::ssize_t k = fp.shape(0);
            require_shape(fq, "fq", k, 3);
            if (P.ndim() != 3 || P.shape(0) != k || P.shape(1) != 3 || P.shape(2) != 3)
                throw py::value_error("P: expected shape (" + std::to_string(k) + ", 3, 3), got " + shape_str(P));
            if (Q.ndim() != 3 || Q.shape(0) != k || Q.shape(1) != 3 || Q.shape(2) != 3)
                throw py::value_error("Q: expected shape (" + std::to_string(k) + ", 3, 3), got " + shape_str(Q));
            require_coordinates(P, "P");
            require_coordinates(Q, "Q");
            py::array_t<bool> out(k);
            for (py::ssize_t i = 0; i < k; ++i) {
                const double* p = P.data() + 9 * i;
                const double* q = Q.data() + 9 * i;
                const Vec3 Pv[3] = {{p[0], p[1], p[2]}, {p[3], p[4], p[5]}, {p[6], p[7], p[8]}};
                const Vec3 Qv[3] = {{q[0], q[1], q[2]}, {q[3], q[4], q[5]}, {q[6], q[7], q[8]}};
                out.mutable_data()[i] = triangles_collide(fp.data() + 3 * i, Pv, fq.data() + 3 * i, Qv);
            }
            return out;
        },
        py::arg("fp"), py::arg("P"), py::arg("fq"), py::arg("Q"),
        "Exact triangle pair test: face ids fp, fq (k, 3) decide shared vertices; positions P, Q (k, 3, 3).");
    // Rows of `pairs` in blocks of four, as the DCD loop runs them (the last block padded with its
    // first pair): bit l of four(V, F, block) is row b + l's answer.
    const auto in_blocks = [](const I32Array& faces, const F64Array& V, const I32Array& pairs, auto four) {
        require_shape(faces, "faces", -1, 3);
        require_points(V, "V", -1, 3);
        require_shape(pairs, "pairs", -1, 2);
        require_indices(faces, "faces", "vertex index", V.shape(0));
        require_indices(pairs, "pairs", "face index", faces.shape(0));
        const int32_t* q = pairs.data();
        const py::ssize_t k = pairs.shape(0);
        py::array_t<bool> out(k);
        bool* o = out.mutable_data();
        for (py::ssize_t b = 0; b < k; b += 4) {
            FacePair block[4];
            for (int l = 0; l < 4; ++l) {
                const py::ssize_t i = b + l < k ? b + l : b;
                block[l] = {q[2 * i], q[2 * i + 1]};
            }
            const uint32_t bits = four(V.data(), faces.data(), block);
            for (int l = 0; l < 4 && b + l < k; ++l) o[b + l] = (bits >> l & 1) != 0;
        }
        return out;
    };
    m.def(
        "triangles_apart",
        [in_blocks](const I32Array& faces, const F64Array& V, const I32Array& pairs, bool portable) {
            return in_blocks(faces, V, pairs, portable ? triangles_apart4_portable : triangles_apart4);
        },
        py::arg("faces"), py::arg("V"), py::arg("pairs"), py::arg("portable") = false,
        "The DCD loop's certified plane rejection (triangles_apart4), four pairs at a time: True where the pair "
        "(rows of faces) is proven not to collide. portable=True: the path without AVX2.");
    m.def(
        "triangles_collide4",
        [in_blocks](const I32Array& faces, const F64Array& V, const I32Array& pairs, bool portable) {
            return in_blocks(faces, V, pairs, portable ? triangles_collide4_portable : triangles_collide4);
        },
        py::arg("faces"), py::arg("V"), py::arg("pairs"), py::arg("portable") = false,
        "The DCD loop's whole pair test (triangles_collide4), four pairs at a time: True where the pair (rows of "
        "faces) collides, as triangles_collide answers. portable=True: the path without AVX2.");
    m.def("triangles_apart_vectorised", &triangles_apart4_vectorised,
          "Whether triangles_apart runs its AVX2 path on this CPU.");
}

}  // namespace conecull::bind
