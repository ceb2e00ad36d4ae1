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

}  // namespace conecull::bind
