// Elementary test bindings (core/include/conecull/elementary/), vectorised over rows.
#include "common.hpp"
#include "conecull/elementary/triangle_triangle.hpp"

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
}

}  // namespace conecull::bind
