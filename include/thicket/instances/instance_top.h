#pragma once
/// The top level of an instanced structure (instances/instances.h): an 8-wide bvh8 tree built with
/// binned SAH over the instances' world boxes, one instance per leaf, in uncompressed nodes,
/// traversed by bvh8's own SIMD kernels with callback leaves. A leaf carries the world ray into
/// its instance's space and calls the bottom level: a triangle `bvh8` directly through its kernel
/// (no virtual call, no wrapper), any other structure through Accel. Empty instances (empty world
/// box) are left out.
///
/// Tried and dropped: compressed nodes (96 bytes instead of 256): a megabyte saved on the 10^4
/// forest, 8% of its shadow rays' speed lost to decoding; a root box test before the kernel (the
/// kernel's first node test answers the same question, so rays that enter paid it twice); one
/// leaf per child of a bvh8 bottom's root (partial re-braiding, Benthin et al. 2017): 8x the top
/// level's leaves and a kernel set-up per part entered, half the primary rays per second.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/bvh8/build.h"
#include "thicket/bvh8/node.h"
#include "thicket/scene/instance.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// A bottom level as the top level's leaves call it: through its bvh8 kernels when it is a
/// non-empty triangle bvh8 (closest[0/1], any[0/1]: without / with counters), else through `accel`.
struct InstanceBottom {
    const Accel* accel = nullptr;
    const bvh8::TraceContext* ctx = nullptr;  ///< null: call accel
    bvh8::ClosestFn closest[2] = {nullptr, nullptr};
    bvh8::AnyFn any[2] = {nullptr, nullptr};

    /// The nearest hit of `local` (a ray in this level's space), counted into *counters when given.
    Hit closest_hit(const Ray& local, RayCounters* counters) const;
    /// Whether `local` hits anything within its interval, counted into *counters when given.
    bool any_hit(const Ray& local, RayCounters* counters) const;
};

/// The bottom-level call of `accel`: its kernels when it is a triangle bvh8 with nodes, else the
/// virtual Accel entries.
InstanceBottom instance_bottom(const Accel& accel);

/// What a leaf needs of one instance, in one cache line: the map of world rays into its space,
/// the flattened id of its first primitive and which bottom level it places.
struct alignas(64) InstanceLeaf {
    RayToInstance to_local;
    uint32_t flat_first = 0;
    uint32_t bottom = 0;  ///< index into the bottoms given to InstanceTop
};

class InstanceTop {
public:
    /// Builds over instance i's world box boxes[i] (leaves[i] what its leaf calls; bottoms what
    /// leaves' `bottom` index) on up to `threads` threads; the kernels of the CPU's best ISA
    /// (capped by THICKET_ISA). Instances with an empty box are never visited.
    InstanceTop(std::span<const Aabb> boxes, std::vector<InstanceLeaf> leaves, std::vector<InstanceBottom> bottoms,
                unsigned threads);
    InstanceTop(const InstanceTop&) = delete;  // ctx_ points into this object
    InstanceTop& operator=(const InstanceTop&) = delete;

    /// The closest hit of the world ray (its prim flattened), or miss_for(ray). counters: null,
    /// or where top nodes, top leaves (an instance tested counts as a primitive) and the bottom
    /// levels' own counts add up.
    Hit closest(const Ray& ray, RayCounters* counters) const;
    /// Whether any instance is hit within [ray.tmin, ray.tmax]; stops at the first.
    bool any(const Ray& ray, RayCounters* counters) const;

    Aabb bounds() const { return tree_.bounds; }
    size_t node_count() const { return tree_.nodes.size(); }
    size_t bytes() const {
        return tree_.nodes.size() * sizeof(bvh8::Node) + ids_.size() * sizeof(uint32_t) +
               leaves_.size() * sizeof(InstanceLeaf) + bottoms_.size() * sizeof(InstanceBottom);
    }
    const bvh8::Tree& tree() const { return tree_; }

    /// What the leaf callbacks read (ctx.prims points at one): the leaves' records in the slots
    /// of the tree's leaf storage (a callback's ids - ids), the bottoms, and the counters of a
    /// counting query (null otherwise).
    struct View {
        const uint32_t* ids;
        const InstanceLeaf* leaves;
        const InstanceBottom* bottoms;
        RayCounters* counters;
    };

private:
    std::vector<InstanceLeaf> leaves_;  ///< in ids_' order once built (a slot per leaf entry)
    std::vector<InstanceBottom> bottoms_;
    std::vector<uint32_t> ids_;  ///< the leaves' instance ids, as the tree's leaves list them
    bvh8::Tree tree_;
    const bvh8::KernelTable* kernels_ = nullptr;
    View view_{};
    bvh8::TraceContext ctx_;
};

}  // namespace thicket

namespace thicket {

/// Boxes whose union holds every vertex of `scene`'s mesh: at most 64, from median splits of the
/// vertices on their widest axis; for a scene of shapes (or no vertices), `bounds` alone. Their
/// corners' images under a transform bound the transformed geometry much closer than the image of
/// one box (a turned box's box), so that fewer rays enter an instance they miss.
std::vector<Aabb> vertex_parts(const Scene& scene, const Aabb& bounds);

/// The world box of geometry held by `parts` (vertex_parts) under `t`: the union of their
/// transform_box images (conservative: each pads its rounding).
Aabb transform_parts(const Affine& t, std::span<const Aabb> parts);

}  // namespace thicket
