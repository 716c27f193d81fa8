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
    /// Rays i with i % brute_stride == 0 hold brute force's answers; the others those of two fast
    /// references of independent code (`bvh`, object partitioning, and `kdtree`, space
    /// partitioning), which agreed with brute force on every one of the former, where they agree
    /// with each other, and brute force's where they do not. 1: all brute.
    size_t brute_stride = 1;
    /// brute_answered[i]: ray i holds brute force's answer (on the stride, or the fast references
    /// differed on it).
    std::vector<uint8_t> brute_answered;
    /// Rays off the stride on which the two fast references differed.
    size_t fast_disagreements = 0;
    /// Judges a ray on which a structure and the fast references differ.
    std::shared_ptr<const Accel> brute;
    bool from_brute(size_t i) const { return brute_answered.empty() ? i % brute_stride == 0 : brute_answered[i] != 0; }
};

/// Answers on conformance_rays(scene, count) with the given `isect` option, cached per process
/// under `key`: brute force's on about `brute_rays` of them spread over the set (every kind of ray)
/// and, when that is fewer than `count`, on the rest those of `bvh` and `kdtree` where the two
/// agree and brute force's where they do not, after both agreed with brute force on all of the
/// former (else throws Error naming the first ray one got wrong). A structure that shares a bug
/// with one of them is still judged by the other, independent one.
const Reference& reference_for(const std::string& key, const Scene& scene, const std::string& isect, size_t count,
                               size_t brute_rays = SIZE_MAX);

/// Runs `accel` over the reference rays (closest, closest with counters, any-hit) and returns
/// "" when it agrees everywhere, else a description of the first few disagreements.
std::string compare_with_reference(const Accel& accel, const Reference& ref, const std::string& scene_name);

/// Most primitive tests one query may make on `accel` over a scene of `primitives`: each
/// primitive once, since structures whose cells share primitives keep a mailbox; except
/// `mailbox=off`, whose point is repeated tests (no bound), and spatial-split BVHs (`bvh` and
/// `bvh8` with builder=sbvh, `bvh8:quality=high`), which list a triangle in several leaves with
/// no mailbox (a per-ray mailbox would cost every ray for the few that reach two leaves of one
/// triangle): at most once per reference they hold (their `references` figure).
size_t most_tests_per_query(const Accel& accel, size_t primitives);

/// Whether stats that leave sah_cost at 0 (undefined) say why under kSahUndefinedKey.
bool sah_cost_explained(const AccelStats& stats);

}  // namespace thicket::testing
