// Topology bindings (core/include/conecull/mesh/topology.hpp).
#include <memory>

#include "common.hpp"
#include "conecull/mesh/topology.hpp"

namespace conecull::bind {

void bind_mesh(py::module_& m) {
    py::class_<Topology, std::shared_ptr<Topology>>(m, "Topology", py::module_local())
        .def_readonly("n_vertices", &Topology::n_vertices)
        .def_property_readonly("n_faces", &Topology::n_faces)
        .def_property_readonly("n_edges", &Topology::n_edges)
        .def_readonly("n_components", &Topology::n_components)
        .def_property_readonly("faces", [](const Topology& t) { return to_numpy(t.faces, 3); })
        .def_property_readonly("edges", [](const Topology& t) { return to_numpy(t.edges, 2); })
        .def_property_readonly("face_edges", [](const Topology& t) { return to_numpy(t.face_edges, 3); })
        .def_property_readonly("edge_face_offsets", [](const Topology& t) { return to_numpy(t.edge_face_offsets); })
        .def_property_readonly("edge_face_ids", [](const Topology& t) { return to_numpy(t.edge_face_ids); })
        .def_property_readonly("vertex_face_offsets", [](const Topology& t) { return to_numpy(t.vertex_face_offsets); })
        .def_property_readonly("vertex_face_ids", [](const Topology& t) { return to_numpy(t.vertex_face_ids); })
        .def_property_readonly("boundary_edges", [](const Topology& t) { return to_numpy(t.boundary_edges); })
        .def_property_readonly("edge_nonmanifold", [](const Topology& t) { return to_numpy(t.edge_nonmanifold); })
        .def_property_readonly("vertex_nonmanifold", [](const Topology& t) { return to_numpy(t.vertex_nonmanifold); })
        .def_property_readonly("face_touches_nonmanifold",
                               [](const Topology& t) { return to_numpy(t.face_touches_nonmanifold); })
        .def_property_readonly("face_component", [](const Topology& t) { return to_numpy(t.face_component); });

    m.def(
        "build_topology",
        [](const I32Array& faces, int64_t n_vertices) {
            require_shape(faces, "faces", -1, 3);
            if (n_vertices < 0 || n_vertices > INT32_MAX) throw py::value_error("n_vertices: must be in [0, 2^31)");
            const int32_t m = static_cast<int32_t>(faces.shape(0));
            const int32_t* f = faces.data();
            for (int64_t i = 0; i < 3 * static_cast<int64_t>(m); ++i)
                if (f[i] < 0 || f[i] >= n_vertices)
                    throw py::value_error("faces: vertex index " + std::to_string(f[i]) + " in row " +
                                          std::to_string(i / 3) + " is out of range [0, " +
                                          std::to_string(n_vertices) + ")");
            for (int32_t i = 0; i < m; ++i)
                if (f[3 * i] == f[3 * i + 1] || f[3 * i + 1] == f[3 * i + 2] || f[3 * i] == f[3 * i + 2])
                    throw py::value_error("faces: row " + std::to_string(i) + " repeats a vertex");
            std::shared_ptr<Topology> t;
            without_gil([&] { t = std::make_shared<Topology>(build_topology(f, m, static_cast<int32_t>(n_vertices))); });
            return t;
        },
        py::arg("faces"), py::arg("n_vertices"),
        "Build the mesh topology from faces (m, 3) int32 with distinct ids in [0, n_vertices).");
}

}  // namespace conecull::bind
