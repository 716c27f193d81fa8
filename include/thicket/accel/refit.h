#pragma once
/// What a structure's refit() reads the moved scene through: the primitive set it was built with,
/// made again from the scene (structures hold copies of their primitives, not the Scene).
#include <cstddef>
#include <string>
#include <type_traits>

#include "thicket/core/error.h"
#include "thicket/prims/mixed.h"
#include "thicket/prims/primitive_set.h"
#include "thicket/prims/triangles.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// The primitive set P of `scene`, made as the build made `built` (accel/dispatch.h: the same
/// triangle test); throws Error naming `structure` when the scene's primitive count is not
/// `expected` (the built one's) or the scene has shapes where P holds triangles only (or the
/// reverse): refit needs the same topology.
template <PrimitiveSet P>
P refit_primitives(const Scene& scene, size_t expected, const P& built, const std::string& structure) {
    if (scene.primitive_count() != expected)
        throw Error(structure + " refit: scene '" + scene.name + "' has " + std::to_string(scene.primitive_count()) +
                    " primitives, the structure was built over " + std::to_string(expected) +
                    "; refit needs the same topology (only vertices may move): rebuild instead");
    if constexpr (std::is_constructible_v<P, const TriangleMesh&>) {
        (void)built;  // a triangle set's test is its type
        if (scene.has_shapes())
            throw Error(structure + " refit: scene '" + scene.name +
                        "' has shapes, the structure was built over triangles only: rebuild instead");
        return P(scene.mesh);
    } else {
        if (!scene.has_shapes())
            throw Error(structure + " refit: scene '" + scene.name +
                        "' has no shapes, the structure was built over shapes: rebuild instead");
        return P(scene.mesh, scene.shapes, scene.runs, scene.name, built.triangle_test());
    }
}

}  // namespace thicket
