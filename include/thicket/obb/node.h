#pragma once
/// The oriented-box node of the OBB tree (Rubin & Whitted 1980: boxes under a rotation) and the
/// flat arrays an OBB tree is made of.
#include <cstdint>
#include <vector>

#include "thicket/core/vec3.h"

namespace thicket {

/// One oriented box and its place in the tree (68 bytes). The box is every point p with
/// |dot(axis[k], p - center)| <= half[k] for k = 0, 1, 2; the axes are orthonormal. A node is a
/// leaf iff count > 0: its primitives are prim_indices[leftFirst .. leftFirst+count). Otherwise
/// its children are nodes leftFirst and leftFirst+1.
struct ObbNode {
    Vec3 axis[3];
    Vec3 center;
    Vec3 half;
    uint32_t leftFirst = 0;
    uint32_t count = 0;

    bool is_leaf() const { return count > 0; }
};
static_assert(sizeof(ObbNode) == 68, "3x3 rotation, centre, half extents, two indices");

/// Deepest tree accepted (the BVH it is made from stays below this) and the traversal stack.
inline constexpr uint32_t kObbMaxDepth = 100;
inline constexpr uint32_t kObbStackSize = 128;

/// A built OBB tree: relocatable (indices only), hence serializable as is. Root at 0, children
/// in adjacent pairs after their parent; empty for a scene without primitives.
struct ObbData {
    std::vector<ObbNode> nodes;
    std::vector<uint32_t> prim_indices;
};

}  // namespace thicket
