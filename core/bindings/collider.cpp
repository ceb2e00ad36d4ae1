// SelfCollider bindings (core/include/conecull/collider.hpp).
#include <memory>
#include <mutex>

#include "conecull/collider.hpp"
#include "conecull/contour/contour_test.hpp"
#include "stages.hpp"

namespace conecull::bind {

namespace {

// One query at a time per collider (queries refit shared state); the GIL is released inside.
struct PyCollider {
    SelfCollider collider;
    std::mutex mutex;
    PyCollider(std::shared_ptr<const Topology> t, Method m, int32_t leaf) : collider(std::move(t), m, leaf) {}
};

const char* reason_name(int r) {
    switch (static_cast<ContourReason>(r)) {
        case ContourReason::kPassed: return "passed";
        case ContourReason::kKernelSignZero: return "kernel_sign_zero";
        case ContourReason::kNotStarShaped: return "not_star_shaped";
        case ContourReason::kRayThroughVertex: return "ray_through_vertex";
        case ContourReason::kMultipleCrossings: return "multiple_crossings";
        case ContourReason::kNoCrossing: return "no_crossing";
    }
    return "unknown";
}

py::dict stats_dict(const DcdStats& s, Method method) {
    py::dict d;
    d["method"] = method_name(method);
    d["bv_tests"] = s.bv_tests;
    d["self_tests"] = s.self_tests;
    d["cone_tests"] = s.cone_tests;
    d["cone_passed"] = s.cone_passed;
    d["contour_ineligible"] = s.contour_ineligible;
    d["contour_tests"] = s.contour_tests;
    d["contour_passed"] = s.contour_passed;
    d["contour_failed"] = s.contour_failed;
    py::dict reasons;
    for (int r = 1; r < static_cast<int>(s.contour_reasons.size()); ++r) reasons[reason_name(r)] = s.contour_reasons[r];
    d["contour_failed_by_reason"] = reasons;
    d["contour_edges"] = s.contour_edges;
    d["elementary_tests"] = s.elementary_tests;
    d["colliding_pairs"] = s.colliding_pairs;
    d["seconds_refit"] = s.seconds_refit;
    d["seconds_traversal"] = s.seconds_traversal;
    d["seconds_elementary"] = s.seconds_elementary;
    return d;
}

py::dict trace_dict(const RecordingTracer& t) {
    py::dict d;
    d["cone_node"] = to_numpy(t.cone_node);
    d["cone_axis"] = to_numpy(t.cone_axis, 3);
    d["cone_apex_angle"] = to_numpy(t.cone_apex_angle);
    d["cone_bounded"] = to_numpy(t.cone_bounded).attr("astype")("bool");
    d["contour_node"] = to_numpy(t.contour_node);
    d["contour_reason"] = to_numpy(t.contour_reason);
    d["contour_edge"] = to_numpy(t.contour_edge);
    d["contour_crossings"] = to_numpy(t.contour_crossings);
    d["contour_kernel"] = to_numpy(t.contour_kernel, 3);
    d["contour_ray"] = to_numpy(t.contour_ray, 3);
    d["level_pairs"] = to_numpy(t.level_pairs);
    d["level_overlaps"] = to_numpy(t.level_overlaps);
    d["elementary_pair"] = to_numpy(t.elementary_pair, 2);
    d["elementary_result"] = to_numpy(t.elementary_result).attr("astype")("bool");
    return d;
}

}  // namespace

void bind_collider(py::module_& m) {
    py::class_<PyCollider, std::shared_ptr<PyCollider>>(m, "SelfCollider", py::module_local())
        .def(py::init([](std::shared_ptr<Topology> topo, const std::string& method, int leaf_size) {
                 if (!topo) throw py::value_error("topology: must not be None");
                 if (leaf_size < 1 || leaf_size > 64) throw py::value_error("leaf_size: must be in [1, 64]");
                 return std::make_shared<PyCollider>(topo, parse_method(method), leaf_size);
             }),
             py::arg("topology"), py::arg("method"), py::arg("leaf_size"))
        .def(
            "dcd",
            [](PyCollider& self, const F64Array& V, bool trace) {
                require_shape(V, "V", self.collider.topology().n_vertices, 3);
                DcdResult res;
                RecordingTracer tracer;
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(self.mutex);
                    res = self.collider.dcd(V.data(), trace ? &tracer : nullptr);
                }
                py::array_t<int64_t> pairs({static_cast<py::ssize_t>(res.pairs.size()), py::ssize_t(2)});
                int64_t* p = pairs.mutable_data();
                for (size_t i = 0; i < res.pairs.size(); ++i) {
                    p[2 * i] = res.pairs[i].first;
                    p[2 * i + 1] = res.pairs[i].second;
                }
                py::object tr = trace ? py::object(trace_dict(tracer)) : py::object(py::none());
                return py::make_tuple(pairs, stats_dict(res.stats, self.collider.method()), tr);
            },
            py::arg("V"), py::arg("trace") = false,
            "DCD query on positions V (n, 3) float64: returns (pairs (k, 2) int64, stats dict, trace dict or None).")
        .def_property_readonly("built", [](PyCollider& self) { return self.collider.built(); })
        .def_property_readonly("method", [](PyCollider& self) { return method_name(self.collider.method()); })
        .def("bvh_arrays", [](PyCollider& self) { return bvh_arrays(self.collider.bvh()); })
        .def("cone_arrays", [](PyCollider& self) { return cone_arrays(self.collider.cones()); })
        .def("contour_arrays", [](PyCollider& self) { return contour_arrays(self.collider.contours()); });
}

}  // namespace conecull::bind
