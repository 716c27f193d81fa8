// Coverage of a primitive by the leaves that list it, for trees with spatial splits (sbvh). A
// leaf's box need not contain such a primitive, only the part the builder clipped into it; the
// union of those parts must be the whole primitive, or a ray hitting the rest would miss it.
//
// The proof cuts the primitive along the faces of its leaves' boxes: a region whose part of the
// primitive lies in one box is covered; otherwise it is cut in two at a face of a box that meets
// that part and strictly crosses it, and both halves are proved. Each cut takes one plane out of
// the part's span, so the recursion ends (held on an explicit stack, with a work bound).
//
// "Lies in a box" is decided on the exact geometry, not on rounded boxes: the part's outward-
// rounded bounds inside the box settle it at once; bounds a few ulps outside (another clip
// order, other rounding than the builder's) are settled by clipping the primitive to the region
// beyond each face of the box, moved one float outwards, and finding nothing there.
#include <cmath>
#include <string>

#include "coverage.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

/// Regions per primitive the proof may cut, per leaf listing it, and the clips and box tests it
/// may spend in all: the builder's trees need a few regions per leaf and a clip or two per
/// region; a file that needs more is refused rather than checked for minutes.
constexpr size_t kRegionsPerLeaf = 1024;
constexpr size_t kMaxClips = size_t(1) << 24;
constexpr size_t kMaxBoxTests = size_t(1) << 30;

bool contains(const Aabb& outer, const Aabb& inner) {
    for (int a = 0; a < 3; ++a)
        if (!(inner.min[a] >= outer.min[a] && inner.max[a] <= outer.max[a])) return false;
    return true;
}

}  // namespace

Aabb CoverageProof::piece(uint32_t prim, const Aabb& region) {
    if (++clips_ > kMaxClips)
        throw Error("invalid BVH: proving primitive " + std::to_string(prim) + " covered needs too much work");
    if (clip_) return clip_(prim, region);
    return intersection(bounds_[prim], region);
}

bool CoverageProof::inside(uint32_t prim, const Aabb& region, const Aabb& part, const Aabb& box) {
    if (contains(box, part)) return true;
    if (intersection(part, box).empty()) return false;
    // Beyond each face, one float out: the exact part reaches there only if it leaves the box.
    for (int a = 0; a < 3; ++a) {
        if (part.min[a] < box.min[a]) {
            Aabb beyond = region;
            beyond.max[a] = std::nextafter(box.min[a], -INFINITY);
            if (!piece(prim, beyond).empty()) return false;
        }
        if (part.max[a] > box.max[a]) {
            Aabb beyond = region;
            beyond.min[a] = std::nextafter(box.max[a], INFINITY);
            if (!piece(prim, beyond).empty()) return false;
        }
    }
    return true;
}

void CoverageProof::check(uint32_t prim, std::span<const Aabb> boxes) {
    const size_t limit = kRegionsPerLeaf * boxes.size() + 64;
    size_t regions_cut = 0;
    std::vector<Aabb> regions{bounds_[prim]};
    auto refuse = [&](const std::string& why) {
        throw Error("invalid BVH: primitive " + std::to_string(prim) + " (in " + std::to_string(boxes.size()) +
                    " leaves) " + why);
    };
    while (!regions.empty()) {
        const Aabb region = regions.back();
        regions.pop_back();
        box_tests_ += 2 * boxes.size();  // the containment search, then the cut search
        if (++regions_cut > limit || box_tests_ > kMaxBoxTests) refuse("needs too much work to prove covered");
        const Aabb part = piece(prim, region);
        if (part.empty()) continue;
        bool covered = false;
        for (const Aabb& box : boxes)
            if ((covered = inside(prim, region, part, box))) break;
        if (covered) continue;
        // A face of a box meeting the part that strictly crosses it.
        int axis = -1;
        float at = 0.0f;
        for (const Aabb& box : boxes) {
            if (intersection(part, box).empty()) continue;
            for (int a = 0; a < 3 && axis < 0; ++a) {
                for (const float f : {box.min[a], box.max[a]})
                    if (part.min[a] < f && f < part.max[a]) {
                        axis = a;
                        at = f;
                        break;
                    }
            }
            if (axis >= 0) break;
        }
        if (axis < 0) refuse("has a part in none of their boxes");
        Aabb below = region, above = region;
        below.max[axis] = at;
        above.min[axis] = at;
        regions.push_back(above);
        regions.push_back(below);
    }
}

}  // namespace thicket
