#pragma once
// float64 rays: traced in double by structures built with precision=double (brute, bvh), refused
// by every other structure with a message naming that option. Query points have no double path
// (closest points and occupancy are computed in float32): queries.cpp refuses float64 ones.
#include <optional>

#include "queries.h"

namespace thicket::python {

/// Whether `obj` is a numpy float64 array (the queries then take this file's path).
bool is_float64_array(const py::handle& obj);

/// cast_rays for float64 rays (..., 6) or (..., 8): the same dict, with t_hit float64 (inf on a
/// miss) and primitive_uvs float64; ids uint32 and primitive_normals float32 as for float32 rays.
/// ValueError naming precision=double when h's structure is not double_precision().
py::dict cast_rays_double(const AccelHandle& h, const py::handle& rays, unsigned threads);

/// test_occlusions for float64 rays; tnear and tfar (rows of 6) as for float32 rays (widened).
/// As for float32 rays, giving them with rows of 8 is a ValueError.
py::array test_occlusions_double(const AccelHandle& h, const py::handle& rays, std::optional<float> tnear,
                                 std::optional<float> tfar, unsigned threads);

/// count_intersections for float64 rays: int32 of the rays' leading shape, the crossings found in
/// double (query/crossings_double.h: the closest hit asked again from just past each one).
py::array count_intersections_double(const AccelHandle& h, const py::handle& rays, unsigned threads);

/// list_intersections for float64 rays: the same dict, with t_hit and primitive_uvs float64.
py::dict list_intersections_double(const AccelHandle& h, const py::handle& rays, unsigned threads);

}  // namespace thicket::python
