#pragma once
// What a recorded trace needs beyond Accel's interface: an any-hit (shadow) query recorded step
// by step, and the corners of the tetrahedra a `tetra` walk names.
#include <array>
#include <cstdint>
#include <optional>

#include "thicket/accel/accel.h"

namespace thicket::explore {

/// Any-hit query of `ray`, recorded into `rec` where the structure records its steps (bvh, grid,
/// tetra: their any-hit traversals take the recorder as they do for the closest hit); elsewhere
/// the totals only, rec.detailed false. Returns whether anything blocks the ray.
bool record_any_hit(const Accel& accel, const Ray& ray, TraversalRecorder& rec);

/// The corners of tetrahedron `id` of a `tetra` structure's mesh; nothing for another structure
/// or an id the mesh does not have.
std::optional<std::array<Vec3, 4>> tetrahedron_corners(const Accel& accel, uint32_t id);

}  // namespace thicket::explore
