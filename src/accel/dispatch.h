#pragma once
/// Chooses the primitive set a structure is instantiated with, from the scene and the spec's
/// `isect` option. Structures are class templates over a PrimitiveSet; this is where a scene's
/// content picks the instantiation: triangle-only scenes get the Triangles fast path, scenes with
/// shapes the mixed set (triangles and shapes behind one id space). Private to the library
/// (src/ is its private include directory): only the register_*.cpp files use it.
#include <memory>
#include <utility>

#include "thicket/accel/registry.h"
#include "thicket/prims/mixed.h"
#include "thicket/prims/triangles.h"

namespace thicket {

/// The `isect` option every structure takes (registry.cpp appends it to each entry).
inline constexpr Choice<TriangleTest> kTriangleTests[] = {
    {"moller", TriangleTest::Moller},
    {"watertight", TriangleTest::Watertight},
};

/// Calls make(prims) with the primitive set matching `spec` for `scene`, returns its result.
template <class Make>
std::unique_ptr<Accel> with_primitives(const Scene& scene, const AccelSpec& spec, Make&& make) {
    const bool watertight = spec.choice("isect", kTriangleTests) == TriangleTest::Watertight;
    if (scene.has_shapes()) {
        if (watertight)
            return make(MixedPrimitives<TriangleTest::Watertight>(scene.mesh, scene.shapes, scene.runs, scene.name));
        return make(MixedPrimitives<TriangleTest::Moller>(scene.mesh, scene.shapes, scene.runs, scene.name));
    }
    if (watertight) return make(Triangles<TriangleTest::Watertight>(scene.mesh));
    return make(Triangles<TriangleTest::Moller>(scene.mesh));
}

}  // namespace thicket
