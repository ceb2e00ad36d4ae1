// Tracing is a template policy (style: "zero-cost tracing"). Every hook call site is
//   if constexpr (Tracer::enabled) tracer.on_...(...);
// so with NullTracer even the arguments of an event are never built.
#pragma once

namespace conecull {

struct NullTracer {
    static constexpr bool enabled = false;
};

// Whether hook call sites exist for a tracer. CONECULL_NO_TRACE_HOOKS builds the benchmark-only
// module conecull._core_nohooks with no call site at all, to measure that the NullTracer
// variant really costs nothing (`conecull bench trace`).
#ifdef CONECULL_NO_TRACE_HOOKS
template <class Tracer>
inline constexpr bool kTraceHooks = false;
#else
template <class Tracer>
inline constexpr bool kTraceHooks = Tracer::enabled;
#endif

}  // namespace conecull
