#pragma once
/// One primitive of a scene, intersected alone: what a reported hit is checked against when its
/// primitive differs from the reference's (a tie must be real, not a wrong id at the right t). The
/// bench's agreement with Embree and the conformance suite both use it.
#include <cstdint>
#include <functional>
#include <string>

#include "thicket/core/ray.h"
#include "thicket/scene/scene.h"

namespace thicket {

class PrimitiveProbe {
public:
    /// Probes `scene` (which must outlive the probe) with the triangle test `isect` names
    /// ("moller" or "watertight"), through the same primitive set the structures hold.
    PrimitiveProbe(const Scene& scene, const std::string& isect);
    /// Probes the triangles of `mesh` alone (ids are triangle indices), as a Triangles set holds them.
    PrimitiveProbe(const TriangleMesh& mesh, const std::string& isect);

    /// Primitive `prim`'s own closest hit on `ray` within [ray.tmin, ray.tmax]; a miss when it
    /// is not hit or `prim` is no primitive of the scene.
    Hit hit(uint32_t prim, const Ray& ray) const;
    /// The scene's primitive count.
    size_t size() const { return count_; }

private:
    size_t count_ = 0;
    std::function<Hit(uint32_t, const Ray&)> hit_;
};

/// Identical answers: the same primitive (or both misses) with the same t, u, v.
bool identical_hits(const Hit& a, const Hit& b);

}  // namespace thicket
