// SelfCollider bindings (core/include/conecull/collider.hpp).
#include <csignal>
#include <memory>
#include <mutex>
#include <string>

#include "conecull/collider.hpp"
#include "conecull/contour/contour_test.hpp"
#include "conecull/interrupt.hpp"
#include "conecull/parallel.hpp"
#include "stages.hpp"

namespace conecull::bind {

namespace {

// One query at a time per collider (queries refit shared state); the GIL is released inside.
struct PyCollider {
    SelfCollider collider;
    std::mutex mutex;
    PyCollider(std::shared_ptr<const Topology> t, Method m, int32_t leaf, int threads)
        : collider(std::move(t), m, leaf, threads) {}
};

// Ctrl-C during a query on Python's main thread (interrupt.hpp). For the query's duration a
// SIGINT handler of ours sets the flag the query reads, then calls the handler it replaced
// (Python's, which notes the signal for the interpreter), so nothing is lost; afterwards the old
// handler is back. Only on the main thread, where Python raises KeyboardInterrupt, and only
// while SIGINT's Python handler is the default one, which raises it: a program with a handler of
// its own (or none) keeps its queries whole.
std::atomic<bool> g_sigint{false};
struct sigaction g_replaced {};
unsigned long g_main_thread = 0;  // threading.main_thread().ident, read at import

// With the GIL: whether a query starting now on this thread may be interrupted.
bool interruptible_here() {
    if (PyThread_get_thread_ident() != g_main_thread) return false;
    // Handles kept for the process (released, never decref'd: a static py::object would be
    // destroyed after the interpreter, without the GIL, which aborts the exit).
    static const py::handle getsignal = py::object(py::module_::import("signal").attr("getsignal")).release();
    static const py::handle sigint = py::object(py::module_::import("signal").attr("SIGINT")).release();
    static const py::handle default_handler =
        py::object(py::module_::import("signal").attr("default_int_handler")).release();
    return getsignal(sigint).is(default_handler);
}

void on_sigint(int sig, siginfo_t* info, void* context) {
    g_sigint.store(true, std::memory_order_relaxed);
    if (g_replaced.sa_flags & SA_SIGINFO) {
        if (g_replaced.sa_sigaction) g_replaced.sa_sigaction(sig, info, context);
    } else if (g_replaced.sa_handler != SIG_DFL && g_replaced.sa_handler != SIG_IGN && g_replaced.sa_handler) {
        g_replaced.sa_handler(sig);
    }
}

// Our SIGINT handler for a query's whole call: installed before the query waits for the
// collider's lock (a Ctrl-C while another thread's query holds it is then not lost), the flag
// handed to the collider under the lock (Interrupting), the replaced handler back at the end.
class SigintScope {
   public:
    // Needs no GIL; interruptible: as interruptible_here() said before the GIL was released.
    explicit SigintScope(bool interruptible) {
        if (!interruptible) return;
        struct sigaction current {};
        if (sigaction(SIGINT, nullptr, &current) != 0) return;
        const bool python_handles = (current.sa_flags & SA_SIGINFO) ? current.sa_sigaction != nullptr
                                                                     : current.sa_handler != SIG_DFL && current.sa_handler != SIG_IGN;
        if (!python_handles) return;
        g_sigint.store(false);
        g_replaced = current;
        struct sigaction ours {};
        ours.sa_sigaction = on_sigint;
        ours.sa_flags = SA_SIGINFO | SA_ONSTACK;
        sigemptyset(&ours.sa_mask);
        installed_ = sigaction(SIGINT, &ours, nullptr) == 0;
    }
    ~SigintScope() {
        if (installed_) sigaction(SIGINT, &g_replaced, nullptr);
    }
    SigintScope(const SigintScope&) = delete;
    SigintScope& operator=(const SigintScope&) = delete;

    // The flag a query under this scope reads; null: not interruptible.
    const std::atomic<bool>* flag() const { return installed_ ? &g_sigint : nullptr; }

    // After an Interrupted query, with the GIL held: the KeyboardInterrupt that Python's default
    // handler raises for the signal, through error_already_set.
    [[noreturn]] static void raise_interrupt() {
        if (PyErr_CheckSignals() == 0) PyErr_SetNone(PyExc_KeyboardInterrupt);
        throw py::error_already_set();
    }

   private:
    bool installed_ = false;
};

// Under the collider's lock: its queries read `flag` until the end of the scope.
class Interrupting {
   public:
    Interrupting(SelfCollider& collider, const std::atomic<bool>* flag) : collider_(collider) {
        collider.set_interrupt(flag);
    }
    ~Interrupting() { collider_.set_interrupt(nullptr); }
    Interrupting(const Interrupting&) = delete;
    Interrupting& operator=(const Interrupting&) = delete;

   private:
    SelfCollider& collider_;
};

// The collider's lock for a snapshot of its structures (bvh_arrays and the like): a query on
// another thread builds or refits them without the GIL, so reading them unlocked can meet a
// half-built vector (a heap corruption, found by racing bvh_arrays with a first query). The GIL
// is released while waiting, so other Python threads run meanwhile; the query never takes the
// GIL while it holds the lock, so this cannot deadlock.
std::unique_lock<std::mutex> lock_for_snapshot(PyCollider& self) {
    std::unique_lock<std::mutex> lock(self.mutex, std::defer_lock);
    py::gil_scoped_release release;
    lock.lock();
    return lock;
}

const char* reason_name(int r) {
    switch (static_cast<ContourReason>(r)) {
        case ContourReason::kPassed: return "passed";
        case ContourReason::kKernelSignZero: return "kernel_sign_zero";
        case ContourReason::kNotStarShaped: return "not_star_shaped";
        case ContourReason::kRayThroughVertex: return "ray_through_vertex";
        case ContourReason::kMultipleCrossings: return "multiple_crossings";
        case ContourReason::kNoCrossing: return "no_crossing";
        case ContourReason::kNoKernelOnSearchLine: return "no_kernel_on_search_line";
        case ContourReason::kEdgesMayOverlap: return "edges_may_overlap";
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
    d["contour_passed_simple"] = s.contour_passed_simple;
    d["contour_failed"] = s.contour_failed;
    py::dict reasons;
    for (int r = 1; r < static_cast<int>(s.contour_reasons.size()); ++r) reasons[reason_name(r)] = s.contour_reasons[r];
    d["contour_failed_by_reason"] = reasons;
    d["contour_edges"] = s.contour_edges;
    d["front_entries"] = s.front_entries;
    d["front_segments"] = s.front_segments;
    d["front_bytes"] = s.front_bytes;
    d["front_added"] = s.front_added;
    d["front_removed"] = s.front_removed;
    d["front_rested"] = s.front_rested;
    d["elementary_tests"] = s.elementary_tests;
    d["colliding_pairs"] = s.colliding_pairs;
    d["seconds_build"] = s.seconds_build;
    d["seconds_refit"] = s.seconds_refit;
    d["seconds_traversal"] = s.seconds_traversal;
    d["seconds_elementary"] = s.seconds_elementary;
    d["seconds_contour"] = s.seconds_contour;
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
    d["contour_kernel_end"] = to_numpy(t.contour_kernel_end, 3);
    d["contour_ray"] = to_numpy(t.contour_ray, 3);
    d["contour_simple"] = to_numpy(t.contour_simple).attr("astype")("bool");
    d["level_pairs"] = to_numpy(t.level_pairs);
    d["level_overlaps"] = to_numpy(t.level_overlaps);
    d["front_node"] = to_numpy(t.front_node);
    d["front_mode"] = to_numpy(t.front_mode);
    d["front_before"] = to_numpy(t.front_before);
    d["front_after"] = to_numpy(t.front_after);
    d["front_box_tests"] = to_numpy(t.front_box_tests);
    d["elementary_pair"] = to_numpy(t.elementary_pair, 2);
    d["elementary_result"] = to_numpy(t.elementary_result).attr("astype")("bool");
    d["vf_pair"] = to_numpy(t.vf_pair, 2);
    d["vf_result"] = to_numpy(t.vf_result).attr("astype")("bool");
    d["ee_pair"] = to_numpy(t.ee_pair, 2);
    d["ee_result"] = to_numpy(t.ee_result).attr("astype")("bool");
    return d;
}

py::array_t<int64_t> pair_rows(const std::vector<std::pair<int32_t, int32_t>>& v) {
    py::array_t<int64_t> a({static_cast<py::ssize_t>(v.size()), py::ssize_t(2)});
    int64_t* p = a.mutable_data();
    for (size_t i = 0; i < v.size(); ++i) {
        p[2 * i] = v[i].first;
        p[2 * i + 1] = v[i].second;
    }
    return a;
}

// 0: the default (all cores for a collider, the collider's for a query).
void check_threads(int threads) {
    if (threads < 0 || threads > kMaxThreads)
        throw py::value_error("threads: expected 0 (default) or a count in [1, " + std::to_string(kMaxThreads) + "], got " +
                              std::to_string(threads));
}

// The query's thread count (traced queries run on one thread), for its input checks
// (require_points). A multi-threaded query wakes the pool's helpers here, before it checks its
// input, which takes tens of microseconds on a large mesh: they are then spinning when its first
// region, the refit, opens (parallel.hpp, ThreadPool::prewake).
int prewake(const PyCollider& self, bool trace, int threads) {
    const int n = trace ? 1 : resolve_threads(threads > 0 ? threads : self.collider.threads());
    ThreadPool::instance().prewake(n);
    return n;
}

Arithmetic parse_arithmetic(const std::string& s) {
    if (s == "float") return Arithmetic::kFloat;
    if (s == "conservative") return Arithmetic::kConservative;
    if (s == "exact") return Arithmetic::kExact;
    throw py::value_error("arithmetic: expected 'float', 'conservative' or 'exact', got '" + s + "'");
}

// Front_X of every node X the last query tracked (bvtt_front.hpp), in traversal order.
py::dict front_arrays(const BvttFront& f, const Bvh& bvh) {
    const py::ssize_t n = static_cast<py::ssize_t>(bvh.nodes.size());
    py::array_t<int32_t> count(n);
    py::array_t<uint8_t> resting(n);
    int32_t* c = count.mutable_data();
    uint8_t* r = resting.mutable_data();
    std::vector<int32_t> owner, ab;
    for (py::ssize_t x = 0; x < n; ++x) {
        const FrontSegment* rec = f.record(static_cast<int32_t>(x));
        c[x] = rec && rec->tracked ? rec->count : 0;
        r[x] = rec ? rec->rest : 0;
        for (int32_t i = 0; i < c[x]; ++i) {
            const FrontEntry& e = f.entries[rec->begin + i];
            owner.push_back(static_cast<int32_t>(x));
            ab.push_back(e.a);
            ab.push_back(e.b);
        }
    }
    py::dict d;
    d["count"] = count;
    d["resting"] = resting;
    d["owner"] = to_numpy(owner);
    d["entries"] = to_numpy(ab, 2);
    return d;
}

}  // namespace

void bind_collider(py::module_& m) {
    g_main_thread = py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
    py::class_<PyCollider, std::shared_ptr<PyCollider>>(m, "SelfCollider", py::module_local())
        .def(py::init([](std::shared_ptr<Topology> topo, const std::string& method, int leaf_size, int threads) {
                 if (!topo) throw py::value_error("topology: must not be None");
                 if (leaf_size < 1 || leaf_size > 64) throw py::value_error("leaf_size: must be in [1, 64]");
                 check_threads(threads);
                 return std::make_shared<PyCollider>(topo, parse_method(method), leaf_size, threads);
             }),
             py::arg("topology"), py::arg("method"), py::arg("leaf_size"), py::arg("threads") = 0,
             "threads: the queries' default thread count, 0 for all cores.")
        .def(
            "dcd",
            [](PyCollider& self, const F64Array& V, bool trace, int threads, bool stop_at_first) {
                check_threads(threads);
                const int checks = prewake(self, trace, threads);
                require_points(V, "V", self.collider.topology().n_vertices, 3, checks);
                DcdResult res;
                RecordingTracer tracer;
                const bool interruptible = interruptible_here();
                try {
                    without_gil([&] {
                        const SigintScope sigint(interruptible);
                        std::lock_guard<std::mutex> lock(self.mutex);
                        const Interrupting watched(self.collider, sigint.flag());
                        res = self.collider.dcd(V.data(), trace ? &tracer : nullptr, threads, stop_at_first);
                    });
                } catch (const Interrupted&) {
                    SigintScope::raise_interrupt();
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
            py::arg("V"), py::arg("trace") = false, py::arg("threads") = 0, py::arg("stop_at_first") = false,
            "DCD query on positions V (n, 3) float64: returns (pairs (k, 2) int64, stats dict, trace dict or None).\n"
            "threads: 0 for the collider's default; the results do not depend on it. stop_at_first: stop at a\n"
            "colliding pair (pairs: it, or none); see SelfCollider.dcd for which one.")
        .def(
            "ccd",
            [](PyCollider& self, const F64Array& V0, const F64Array& V1, const std::string& arithmetic, bool trace,
               bool toi, int threads, bool stop_at_first) {
                const int32_t n = self.collider.topology().n_vertices;
                check_threads(threads);
                const int checks = prewake(self, trace, threads);
                require_points(V0, "V0", n, 3, checks);
                require_points(V1, "V1", n, 3, checks);
                const Arithmetic mode = parse_arithmetic(arithmetic);
                CcdResult res;
                RecordingTracer tracer;
                const bool interruptible = interruptible_here();
                try {
                    without_gil([&] {
                        const SigintScope sigint(interruptible);  // as dcd
                        std::lock_guard<std::mutex> lock(self.mutex);
                        const Interrupting watched(self.collider, sigint.flag());
                        res = self.collider.ccd(V0.data(), V1.data(), mode, trace ? &tracer : nullptr, toi, threads,
                                                stop_at_first);
                    });
                } catch (const Interrupted&) {
                    SigintScope::raise_interrupt();
                }
                py::dict st = stats_dict(res.stats, self.collider.method());
                const CcdStats& c = res.stats;
                st["vf_candidates"] = c.vf_candidates;
                st["ee_candidates"] = c.ee_candidates;
                st["npf_culled"] = c.npf_culled;
                st["vf_tests"] = c.vf_tests;
                st["ee_tests"] = c.ee_tests;
                st["vf_contacts"] = c.vf_contacts;
                st["ee_contacts"] = c.ee_contacts;
                st["seconds_pairs"] = c.seconds_pairs;
                st["arithmetic"] = arithmetic;
                if (mode == Arithmetic::kExact) {
                    py::dict e;
                    e["filtered"] = c.exact_paths.filtered;
                    e["static_contact"] = c.exact_paths.static_contact;
                    e["proven_contact"] = c.exact_paths.proven_contact;
                    e["interval_filtered"] = c.exact_paths.interval_filtered;
                    e["exact_engine"] = c.exact_paths.exact_engine;
                    st["exact_paths"] = e;
                }
                py::object tr = trace ? py::object(trace_dict(tracer)) : py::object(py::none());
                py::object t = toi ? py::object(to_numpy(res.toi)) : py::object(py::none());
                return py::make_tuple(pair_rows(res.vf), pair_rows(res.ee), st, tr, t);
            },
            py::arg("V0"), py::arg("V1"), py::arg("arithmetic"), py::arg("trace") = false, py::arg("toi") = false,
            py::arg("threads") = 0, py::arg("stop_at_first") = false,
            "CCD over the step V0 -> V1: returns (vf (k, 2), ee (k, 2), stats dict, trace dict or None, toi or None).\n"
            "stop_at_first: make and test each candidate's VF then EE pairs as it is reached, up to the first\n"
            "contact (vf or ee: it, or none); aabb / nc stop traversing there too (see SelfCollider.ccd).")
        .def_property_readonly("built",
                               [](PyCollider& self) {
                                   const auto lock = lock_for_snapshot(self);
                                   return self.collider.built();
                               })
        .def_property_readonly("method", [](PyCollider& self) { return method_name(self.collider.method()); })
        .def_property_readonly("threads", [](PyCollider& self) { return self.collider.threads(); })
        .def("bvh_arrays",
             [](PyCollider& self) {
                 const auto lock = lock_for_snapshot(self);
                 return bvh_arrays(self.collider.bvh());
             })
        .def("cone_arrays",
             [](PyCollider& self) {
                 const auto lock = lock_for_snapshot(self);
                 return cone_arrays(self.collider.cones());
             })
        .def("contour_arrays",
             [](PyCollider& self) {
                 const auto lock = lock_for_snapshot(self);
                 return contour_arrays(self.collider.contours());
             })
        .def(
            "front_arrays",
            [](PyCollider& self, bool continuous) {
                const auto lock = lock_for_snapshot(self);
                return front_arrays(self.collider.front(continuous), self.collider.bvh());
            },
            py::arg("continuous"),
            "The BVTT front the last DCD (continuous=False) or CCD query left: per entry its BVTT node (a, b) "
            "and the internal node X whose sub-segment Front_X holds it; per BVH node the sub-segment size.");
}

}  // namespace conecull::bind
