// Tracing is a template policy (style: "zero-cost tracing"). Every hook call site is
//   if constexpr (Tracer::enabled) tracer.on_...(...);
// so with NullTracer even the arguments of an event are never built.
#pragma once

namespace conecull {

struct NullTracer {
    static constexpr bool enabled = false;
};

}  // namespace conecull
