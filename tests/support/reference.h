#pragma once
// Brute-force references, computed once per (scene, triangle test), and the agreement rule.
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
};

/// Brute force's answers on conformance_rays(scene, count) with the given `isect` option;
/// cached per process under `key`.
const Reference& reference_for(const std::string& key, const Scene& scene, const std::string& isect, size_t count);

/// Runs `accel` over the reference rays (closest, closest with counters, any-hit) and returns
/// "" when it agrees everywhere, else a description of the first few disagreements.
std::string compare_with_reference(const Accel& accel, const Reference& ref, const std::string& scene_name);

/// Whether stats that leave sah_cost at 0 (undefined) say why under kSahUndefinedKey.
bool sah_cost_explained(const AccelStats& stats);

}  // namespace thicket::testing
