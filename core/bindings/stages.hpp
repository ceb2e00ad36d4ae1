// Array exports shared between the stage bindings and the collider binding.
#pragma once

#include "common.hpp"
#include "conecull/bvh/bvh.hpp"
#include "conecull/cone/normal_cone.hpp"
#include "conecull/contour/contour.hpp"
#include "conecull/contour/contour_test.hpp"

namespace conecull::bind {

py::dict bvh_arrays(const Bvh& bvh);
py::dict cone_arrays(const std::vector<NormalCone>& cones);
py::dict contour_arrays(const Contours& contours);
py::dict verdict_dict(const ContourVerdict& v);

// Validated (loop, axis) of the single-loop contour tests; positions checked by the caller.
// A loop of vertex ids (n,) with n >= 3 into V (one pose) or V0, V1 (a step, same shape), and the
// axis l (3,): each argument checked, with its name in the error; returns l.
Vec3 check_loop_pose(const I32Array& loop, const F64Array& V, const F64Array& l);
Vec3 check_loop_step(const I32Array& loop, const F64Array& V0, const F64Array& V1, const F64Array& l);

// The optional choices of the single-loop tests (Alg. 1 and Alg. 3): `kernel` fixes the kernel
// point (K: a point; for CCD its two ends), r the ray (with r alone, the kernel is mean());
// neither: the core's full test. attempt(r, kernel) runs one attempt, full() the core's test
// (the mean, then the clipped kernel's point; ray retries).
template <class K, class Mean, class Attempt, class Full>
ContourVerdict contour_test_choosing(const Vec3& axis, const std::optional<Vec3>& ray, const std::optional<K>& kernel,
                                     const Mean& mean, const Attempt& attempt, const Full& full) {
    if (!ray && !kernel) return full();
    const K o = kernel ? *kernel : mean();
    if (ray) return attempt(*ray, o);
    return with_ray_retry(axis, [&](const Vec3& d) { return attempt(d, o); });
}

}  // namespace conecull::bind
