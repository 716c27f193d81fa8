#pragma once
/// The Utah teapot as Martin Newell published it (1975): 32 bicubic Bezier patches over 306
/// control vertices, in the groups rim (4), body (8), handle (4), spout (4), lid (8) and
/// bottom (4). Newell's data is z-up; teapot_patches() turns it y-up for thicket.
#include <array>
#include <span>
#include <vector>

#include "thicket/core/vec3.h"
#include "thicket/prims/bezier.h"

namespace thicket {

inline constexpr int kTeapotPatchCount = 32;
inline constexpr int kTeapotVertexCount = 306;

enum class TeapotGroup { Rim, Body, Handle, Spout, Lid, Bottom };

/// The 306 control vertices exactly as published (z-up; the bottom at z = 0, the lid's knob
/// at z = 3.15). Index 0 is Newell's vertex 1.
std::span<const Vec3, kTeapotVertexCount> teapot_newell_vertices();
/// Per patch the 16 control vertex numbers as published (1-based, row by row: entry 4 * j + i
/// is control point (i, j) of BezierPatch).
std::span<const std::array<int, 16>, kTeapotPatchCount> teapot_newell_patches();
/// The group patch p (0-based, in published order) belongs to.
TeapotGroup teapot_group(int patch);
const char* teapot_group_name(TeapotGroup g);

/// The 32 patches in thicket's y-up frame: Newell's (x, y, z) becomes (x, z, -y), a rotation
/// about x (so the outward orientation of dP/du x dP/dv is kept). Units as published: the
/// bounds are about x in [-3, 3.43], y in [0, 3.15], z in [-2, 2].
std::vector<BezierPatch> teapot_patches();

}  // namespace thicket
