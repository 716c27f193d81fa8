#pragma once
/// The BVH in double precision (`bvh:precision=double`): the tree is built by the float builders
/// over each triangle's box rounded outward to float, then every node gets a double box, the
/// union of its triangles' double boxes (so the boxes are exact in double whatever float did),
/// and rays are traced in double against those boxes and the double triangles.
#include <cstdint>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/bvh/build.h"
#include "thicket/bvh/traversal.h"
#include "thicket/core/aligned.h"
#include "thicket/prims/triangles.h"

namespace thicket {

/// A node with double bounds: the float BvhNode's layout, 64 bytes (one cache line).
struct alignas(64) BvhNodeD {
    Vec3d lo;
    uint32_t leftFirst = 0;
    uint32_t count = 0;
    Vec3d hi;
};
static_assert(sizeof(BvhNodeD) == 64, "one double node per cache line");

template <TriangleTest Test>
class BvhD final : public AccelBase<BvhD<Test>> {
    friend class AccelBase<BvhD<Test>>;

public:
    static constexpr bool kDoublePrecision = true;

    /// Builds over `prims` with the float builders (options.builder etc.), traced in `traversal`
    /// order (recursive and stack visit the same nodes; the ordered ones pick the near child as
    /// the float BVH does).
    BvhD(TrianglesD<Test> prims, const BvhBuildOptions& options, BvhTraversal traversal)
        : prims_(std::move(prims)), traversal_(traversal) {
        std::vector<Aabb> bounds;
        std::vector<Vec3> centroids;
        primitive_boxes(
            uint32_t(prims_.size()), options.threads, bounds, centroids,
            [&](uint32_t i) { return outward_float_box(prims_.bounds(i)); },
            [&](uint32_t i) { return prims_.centroid(i).to_float(); });
        // No clip function: spatial splits (sbvh) cut the float boxes, which is conservative.
        data_ = build_bvh({bounds, centroids, {}}, options);
        nodes_.resize(data_.nodes_used);
        if (data_.nodes_used) fill_boxes(0);
    }

    Aabb bounds() const override {
        if (nodes_.empty()) return Aabb{};
        AabbD b;
        b.grow(nodes_[0].lo);
        b.grow(nodes_[0].hi);
        return outward_float_box(b);
    }

    AccelStats stats() const override {
        const BvhFigures f = bvh_figures(data_);  // of the float boxes the builder chose
        AccelStats s = this->tree_stats(f, prims_.size(),
                                        nodes_.size() * (sizeof(BvhNodeD) + sizeof(BvhNode) + 1) +
                                            data_.prim_indices.size() * sizeof(uint32_t),
                                        prims_.bytes());
        s.extra.emplace_back("precision", "double (nodes, triangles and rays)");
        s.extra.emplace_back("largest leaf", std::to_string(f.max_leaf_size));
        s.extra.emplace_back("references", reference_figure(data_.prim_indices.size(), prims_.size()));
        return s;
    }

private:
    /// Node n's double box from its subtree (children come after parents, depth < kMaxDepth).
    AabbD fill_boxes(uint32_t n) {
        const BvhNode& f = data_.nodes[n];
        AabbD box;
        if (f.is_leaf()) {
            for (uint32_t i = f.leftFirst; i < f.leftFirst + f.count; ++i) box.grow(prims_.bounds(data_.prim_indices[i]));
        } else {
            box.grow(fill_boxes(f.leftFirst));
            box.grow(fill_boxes(f.leftFirst + 1));
        }
        nodes_[n] = {box.min, f.leftFirst, f.count, box.max};
        return box;
    }

    /// Closest hit (AnyHit false) or any hit, in the order traversal_ asks for.
    template <bool AnyHit, class C>
    bool trace(const RayD& ray, HitD& hit, C& counters) const {
        if (nodes_.empty()) return false;
        constexpr double kMissed = std::numeric_limits<double>::infinity();
        const RayBoxQueryD box(ray);
        auto far = [&] { return AnyHit ? ray.tmax : hit.t; };
        auto enter = [&](uint32_t n) {
            counters.node();
            return ray_box_entry(box, nodes_[n].lo, nodes_[n].hi, ray.tmin, far());
        };
        auto leaf = [&](const BvhNodeD& node) {
            for (uint32_t i = node.leftFirst, end = node.leftFirst + node.count; i < end; ++i) {
                counters.prim();
                if constexpr (AnyHit) {
                    if (prims_.occludes(data_.prim_indices[i], ray)) return true;
                } else {
                    prims_.intersect(data_.prim_indices[i], ray, hit);
                }
            }
            return false;
        };
        struct Entry {
            uint32_t node;
            double t;
        };
        Entry stack[kTraversalStackSize];
        uint32_t sp = 0;
        if (traversal_ == BvhTraversal::Recursive || traversal_ == BvhTraversal::Stack) {
            // Boxes tested when popped, left child first: the slide's order.
            stack[sp++] = {0, 0.0};
            while (sp > 0) {
                const uint32_t n = stack[--sp].node;
                if (enter(n) == kMissed) continue;
                const BvhNodeD& node = nodes_[n];
                if (node.count > 0) {
                    if (leaf(node)) return true;
                } else {
                    stack[sp++] = {node.leftFirst + 1, 0.0};
                    stack[sp++] = {node.leftFirst, 0.0};
                }
            }
            return false;
        }
        // Ordered traversal (core/ordered_traversal.h) with double entry distances.
        if (enter(0) == kMissed) return false;
        uint32_t n = 0;
        for (;;) {
            const BvhNodeD& node = nodes_[n];
            if (node.count > 0) {
                if (leaf(node)) return true;
            } else {
                uint32_t near = node.leftFirst, far_node = near + 1;
                double t_near = enter(near), t_far = enter(far_node);
                if (second_first(n, box, t_near, t_far)) {
                    std::swap(near, far_node);
                    std::swap(t_near, t_far);
                }
                if (t_near != kMissed) {
                    if (t_far != kMissed) stack[sp++] = {far_node, t_far};
                    n = near;
                    continue;
                }
                if (t_far != kMissed) {
                    n = far_node;
                    continue;
                }
            }
            for (;;) {
                if (sp == 0) return false;
                const Entry e = stack[--sp];
                if (e.t <= far()) {
                    n = e.node;
                    break;
                }
            }
        }
    }

    /// Whether node n's second child goes first: as bvh_detail::Query::ordered picks.
    bool second_first(uint32_t n, const RayBoxQueryD& box, double t_first, double t_second) const {
        switch (traversal_) {
        case BvhTraversal::OrderedAxis: return box.neg[ChildOrder::split_axis(data_.child_order[n])] != 0;
        case BvhTraversal::OrderedCentroid: {
            const uint8_t order = data_.child_order[n];
            return (box.neg[ChildOrder::centroid_axis(order)] != 0) != ChildOrder::left_is_higher(order);
        }
        default: return t_second < t_first;
        }
    }

    template <class C>
    HitD closest(const RayD& ray, C& counters) const {
        HitD hit = miss_for(ray);
        trace<false>(ray, hit, counters);
        return hit;
    }
    template <class C>
    bool any(const RayD& ray, C& counters) const {
        HitD unused;
        return trace<true>(ray, unused, counters);
    }

    TrianglesD<Test> prims_;
    BvhData data_;  ///< the float builder's tree: topology, leaf order and child order bytes
    AlignedVector<BvhNodeD, 64> nodes_;
    BvhTraversal traversal_;
};

}  // namespace thicket
