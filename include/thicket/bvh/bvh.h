#pragma once
/// The lecture's BVH over any primitive set: build with one of three builders, trace with one
/// of five traversals. Usable directly (no virtual call) or through the Accel interface.
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/accel/refit.h"
#include "thicket/bvh/build.h"
#include "thicket/bvh/closest_point.h"
#include "thicket/bvh/draw.h"
#include "thicket/bvh/refit.h"
#include "thicket/bvh/traversal.h"

namespace thicket {

template <PrimitiveSet Prims>
class Bvh final : public AccelBase<Bvh<Prims>> {
public:
    /// Builds over `prims`.
    Bvh(Prims prims, const BvhBuildOptions& options, BvhTraversal traversal = BvhTraversal::OrderedDistance)
        : prims_(std::move(prims)), traversal_(traversal) {
        std::vector<Aabb> bounds;
        std::vector<Vec3> centroids;
        primitive_boxes(
            uint32_t(prims_.size()), options.threads, bounds, centroids,
            [&](uint32_t i) { return prims_.bounds(i); }, [&](uint32_t i) { return prims_.centroid(i); });
        data_ = build_bvh({bounds, centroids, clip_function()}, options);
    }

    /// Adopts an already built (e.g. loaded) BVH after checking it fits `prims`.
    Bvh(Prims prims, BvhData data, BvhTraversal traversal)
        : prims_(std::move(prims)), data_(std::move(data)), traversal_(traversal) {
        validate_bvh(data_, prims_.size());
        std::vector<Aabb> bounds(prims_.size());
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds[i] = prims_.bounds(i);
        validate_bvh_bounds(data_, bounds, clip_function());
    }

    Aabb bounds() const override { return data_.nodes_used ? data_.nodes[0].bounds() : Aabb{}; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        return closest_hit<bvh_detail::Query>(data_, prims_, ray, counters, traversal_);
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        return any_hit<bvh_detail::Query>(data_, prims_, ray, counters, traversal_);
    }

    /// Both traversals report their steps to a TraversalRecorder (Accel::intersect, occluded).
    static constexpr bool kRecordsSteps = true;
    static constexpr bool kRecordsAnyHitSteps = true;
    NearestPoint closest_point(const Vec3& p) const override {
        if constexpr (HasClosestPoint<Prims>)
            return bvh_closest_point(data_, prims_, p);
        else
            return Accel::closest_point(p);  // shapes: refused with the reason
    }
    bool has_closest_point() const override { return HasClosestPoint<Prims>; }

    AccelStats stats() const override {
        const BvhFigures f = bvh_figures(data_);
        AccelStats s = this->tree_stats(
            f, prims_.size(),
            size_t(data_.nodes_used) * (sizeof(BvhNode) + 1) + data_.prim_indices.size() * sizeof(uint32_t),
            prims_.bytes());
        s.extra.emplace_back("largest leaf", std::to_string(f.max_leaf_size));
        // More references than primitives: spatial splits (builder=sbvh) list some in several leaves.
        s.extra.emplace_back("references", reference_figure(data_.prim_indices.size(), prims_.size()));
        s.extra.emplace_back("node pool", std::to_string(data_.nodes.capacity()) + " nodes allocated, " +
                                              std::to_string(data_.nodes_used) + " used (slot 1 unused)");
        return s;
    }

    void save(std::ostream& out) const override { write_bvh(out, data_); }

    /// Accel::refit: the scene's primitives again, every box recomputed (src/bvh/refit.cpp).
    void refit(const Scene& scene, unsigned threads) override {
        Prims fresh = refit_primitives(scene, prims_.size(), prims_, "bvh");
        refit_bvh(data_, refit_boxes(fresh, threads));
        prims_ = std::move(fresh);
    }
    bool refittable() const override { return true; }

    const BvhData& data() const { return data_; }
    const Prims& primitives() const { return prims_; }

private:
    /// The exact clip of the primitive set (clipped_bounds: triangles clipped, shapes' boxes cut).
    ClipFunction clip_function() const {
        return [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); };
    }

    Prims prims_;
    BvhData data_;
    BvhTraversal traversal_;
};

}  // namespace thicket
