// conecull._core: the private compiled module behind the conecull package. Submodules mirror
// the pipeline stages of core/include/conecull/.
#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace conecull::bind {
void bind_mesh(py::module_& m);
void bind_bvh(py::module_& m);
void bind_predicates(py::module_& m);
void bind_cone(py::module_& m);
void bind_contour(py::module_& m);
void bind_elementary(py::module_& m);
void bind_collider(py::module_& m);
void bind_ccd(py::module_& m);
void bind_traversal(py::module_& m);
void bind_parallel(py::module_& m);
}  // namespace conecull::bind

#ifndef CONECULL_MODULE_NAME
#define CONECULL_MODULE_NAME _core
#endif

PYBIND11_MODULE(CONECULL_MODULE_NAME, m) {
    using namespace conecull::bind;
    m.doc() = "conecull compiled core (private; use the conecull package)";
    bind_mesh(m);
    bind_bvh(m);
    auto predicates = m.def_submodule("predicates", "Exact sign predicates, vectorised over rows");
    bind_predicates(predicates);
    auto cone = m.def_submodule("cone", "Normal cones");
    bind_cone(cone);
    auto contour = m.def_submodule("contour", "Unprojected contour test (Alg. 1)");
    bind_contour(contour);
    auto elementary = m.def_submodule("elementary", "Exact elementary tests");
    bind_elementary(elementary);
    auto ccd = m.def_submodule("ccd", "Continuous collision detection: cones and Alg. 3");
    bind_ccd(ccd);
    auto traversal = m.def_submodule("traversal", "BVTT traversal (Alg. 2, 4): the first-hit order");
    bind_traversal(traversal);
    auto parallel = m.def_submodule("parallel", "The thread pool: its parallel ceiling on this machine");
    bind_parallel(parallel);
    bind_collider(m);
}
