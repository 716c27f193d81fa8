#pragma once
// float64 rays: traced in double by structures built with precision=double (brute, bvh), refused
// by every other structure with a message naming that option.
#include <optional>

#include "queries.h"

namespace thicket::python {

/// Whether `obj` is a numpy float64 array (the queries then take this file's path).
bool is_float64_array(const py::handle& obj);

/// cast_rays for float64 rays (..., 6) or (..., 8): the same dict, with t_hit float64 (inf on a
/// miss) and primitive_uvs float64; ids uint32 and primitive_normals float32 as for float32 rays.
/// ValueError naming precision=double when h's structure is not double_precision().
py::dict cast_rays_double(const AccelHandle& h, const py::handle& rays, unsigned threads);

/// test_occlusions for float64 rays; tnear and tfar (rows of 6) as for float32 rays.
py::array test_occlusions_double(const AccelHandle& h, const py::handle& rays, std::optional<double> tnear,
                                 std::optional<double> tfar, unsigned threads);

}  // namespace thicket::python
