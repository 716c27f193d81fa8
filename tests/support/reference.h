#pragma once
// Brute-force references, computed once per (scene, triangle test), and the agreement rule.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "support/probe.h"
#include "thicket/accel/accel.h"
#include "thicket/scene/scene.h"

namespace thicket::testing {

struct Reference {
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    std::vector<uint8_t> occluded;
    std::shared_ptr<const PrimitiveProbe> probe;  ///< the scene's primitives, one at a time
    /// Rays i with i % brute_stride == 0 hold brute force's answers, the others those of the fast
    /// reference (`bvh`), which agreed with brute force on every one of the former. 1: all brute.
    size_t brute_stride = 1;
    /// Judges a ray on which a structure and the fast reference differ.
    std::shared_ptr<const Accel> brute;
    bool from_brute(size_t i) const { return i % brute_stride == 0; }
};

/// Answers on conformance_rays(scene, count) with the given `isect` option, cached per process
/// under `key`: brute force's on about `brute_rays` of them spread over the set (every kind of ray)
/// and, when that is fewer than `count`, the `bvh`'s on the rest, after it agreed with brute force
/// on all of the former (else throws Error naming the first ray it got wrong).
const Reference& reference_for(const std::string& key, const Scene& scene, const std::string& isect, size_t count,
                               size_t brute_rays = SIZE_MAX);

/// Runs `accel` over the reference rays (closest, closest with counters, any-hit) and returns
/// "" when it agrees everywhere, else a description of the first few disagreements.
std::string compare_with_reference(const Accel& accel, const Reference& ref, const std::string& scene_name);

/// Whether stats that leave sah_cost at 0 (undefined) say why under kSahUndefinedKey.
bool sah_cost_explained(const AccelStats& stats);

}  // namespace thicket::testing
