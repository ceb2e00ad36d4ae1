// Parallel bindings (core/include/conecull/parallel.hpp): what the thread pool can deliver on
// this machine right now, for `conecull bench threads`.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "common.hpp"
#include "conecull/parallel.hpp"

namespace conecull::bind {

void bind_parallel(py::module_& m) {
    m.def(
        "compute_ceiling",
        [](int threads, int64_t chunks, int64_t iterations) {
            if (threads < 1 || threads > kMaxThreads)
                throw py::value_error("threads: expected a count in [1, " + std::to_string(kMaxThreads) + "], got " +
                                      std::to_string(threads));
            if (chunks < 1 || chunks > (1 << 20))
                throw py::value_error("chunks: expected a count in [1, 1048576], got " + std::to_string(chunks));
            if (iterations < 1 || iterations > 1000000000)
                throw py::value_error("iterations: expected a count in [1, 1e9], got " + std::to_string(iterations));
            double seconds = 0;
            without_gil([&] {
                if (threads > 1) ThreadPool::instance().prewake(threads);  // as a query does
                std::vector<Padded<double>> out(static_cast<size_t>(chunks));
                const auto t0 = std::chrono::steady_clock::now();
                // One dependent multiply-add chain per chunk: no memory traffic and nothing to
                // share, so the speed-up over one thread is the most the pool can give.
                parallel_chunks(chunks, threads, [&](int64_t c, int) {
                    double x = 1.0 + 1e-3 * static_cast<double>(c);
                    for (int64_t i = 0; i < iterations; ++i) x = x * 0.9999999 + 1e-7;
                    out[static_cast<size_t>(c)].value = x;
                });
                seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                double sum = 0;  // read the results, so the loops are not optimised away
                for (const auto& o : out) sum += o.value;
                if (!(sum > 0)) seconds = -1;  // unreachable: every chain stays near 1
            });
            return seconds;
        },
        py::arg("threads"), py::arg("chunks") = 64, py::arg("iterations") = 200000,
        "Wall seconds of a pure compute loop (chunks x iterations dependent multiply-adds) run by the "
        "core's thread pool on `threads` threads. Its 1-thread time over its 2-thread time is the "
        "machine's parallel ceiling at that moment (bench threads reports it).");
}

}  // namespace conecull::bind
