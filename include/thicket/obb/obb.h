#pragma once
/// The oriented bounding box tree (Rubin & Whitted 1980) over any primitive set: a BVH's
/// topology with every box refitted as an oriented box. Usable directly or through Accel.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/obb/draw.h"
#include "thicket/accel/refit.h"
#include "thicket/bvh/build.h"
#include "thicket/obb/build.h"
#include "thicket/obb/traversal.h"

namespace thicket {

/// Options of the OBB tree: the BVH it is made from, and how boxes are oriented.
struct ObbBuildOptions {
    BvhBuildOptions bvh;
    ObbFit fit = ObbFit::Pca;
};

/// The points a primitive is fitted by: a triangle's vertices, any other shape's box corners.
template <PrimitiveSet Prims>
ObbPoints obb_points(const Prims& prims) {
    ObbPoints p;
    p.offsets.reserve(prims.size() + 1);
    p.offsets.push_back(0);
    for (uint32_t i = 0; i < prims.size(); ++i) {
        if constexpr (kHasTriangles<Prims>) {
            for (const Vec3& v : prims.triangle(i)) p.points.push_back(v);
        } else {
            const Aabb b = prims.bounds(i);
            for (int c = 0; c < 8; ++c)
                p.points.push_back({(c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y,
                                    (c & 4) ? b.max.z : b.min.z});
        }
        p.offsets.push_back(uint32_t(p.points.size()));
    }
    return p;
}

template <PrimitiveSet Prims>
class Obb final : public AccelBase<Obb<Prims>> {
public:
    /// Builds a BVH over `prims`, then fits an oriented box to every node.
    Obb(Prims prims, const ObbBuildOptions& options) : prims_(std::move(prims)) {
        std::vector<Aabb> bounds;
        std::vector<Vec3> centroids;
        primitive_boxes(
            uint32_t(prims_.size()), options.bvh.threads, bounds, centroids,
            [&](uint32_t i) { return prims_.bounds(i); }, [&](uint32_t i) { return prims_.centroid(i); });
        const BvhData bvh = build_bvh({bounds, centroids}, options.bvh);
        data_ = build_obb(bvh, obb_points(prims_), options.fit, scene_scale(), options.bvh.threads);
    }

    /// Adopts an already built (e.g. loaded) tree after proving it fits `prims`: structure,
    /// then every box around the primitives below it (a shrunk box would cull hits).
    Obb(Prims prims, ObbData data) : prims_(std::move(prims)), data_(std::move(data)) {
        validate_obb(data_, prims_.size());
        validate_obb_bounds(data_, obb_points(prims_), scene_scale());
    }

    /// The union of the primitives' boxes (the oriented root box is not axis-aligned).
    Aabb bounds() const override {
        Aabb b;
        for (uint32_t i = 0; i < prims_.size(); ++i) b.grow(prims_.bounds(i));
        return b;
    }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        return closest_hit<obb_detail::Query>(data_, prims_, ray, counters);
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        return any_hit<obb_detail::Query>(data_, prims_, ray, counters);
    }

    AccelStats stats() const override;

    void save(std::ostream& out) const override { write_obb(out, data_); }

    /// Accel::refit: the scene's primitives again, each node's box refitted along its own axes.
    void refit(const Scene& scene, unsigned threads) override {
        prims_ = refit_primitives(scene, prims_.size(), prims_, "obb");
        refit_obb(data_, obb_points(prims_), scene_scale(), threads);
    }
    bool refittable() const override { return true; }

    const ObbData& data() const { return data_; }

private:
    /// Largest coordinate magnitude or extent of the scene: the unit of the boxes' margin.
    float scene_scale() const {
        const Aabb b = bounds();
        if (b.empty()) return 1.0f;
        return std::max({max_component(abs(b.min)), max_component(abs(b.max)), max_component(b.extent())});
    }

    /// SAH cost of the same tree with axis-aligned boxes (the bvh's), relative to `root_area`.
    double aabb_sah(float root_area) const;

    Prims prims_;
    ObbData data_;
};

template <PrimitiveSet Prims>
double Obb<Prims>::aabb_sah(float root_area) const {
    if (data_.nodes.empty() || !(root_area > 0.0f)) return 0.0;
    // Children follow their parents: a backward sweep makes every box before its parent's.
    std::vector<Aabb> boxes(data_.nodes.size());
    for (size_t n = data_.nodes.size(); n-- > 0;) {
        const ObbNode& node = data_.nodes[n];
        if (node.is_leaf()) {
            for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i)
                boxes[n].grow(prims_.bounds(data_.prim_indices[i]));
        } else {
            boxes[n].grow(boxes[node.leftFirst]);
            boxes[n].grow(boxes[node.leftFirst + 1]);
        }
    }
    double cost = 0.0;
    for (size_t n = 0; n < data_.nodes.size(); ++n) {
        const double rel = double(boxes[n].half_area()) / root_area;
        const ObbNode& node = data_.nodes[n];
        cost += node.is_leaf() ? rel * kSahIntersectionCost * node.count : rel * kSahTraversalCost;
    }
    return cost;
}

template <PrimitiveSet Prims>
AccelStats Obb<Prims>::stats() const {
    const float root_area = bounds().half_area();
    const TreeFigures f = obb_figures(data_, root_area);
    const size_t bytes = data_.nodes.size() * sizeof(ObbNode) + data_.prim_indices.size() * sizeof(uint32_t);
    AccelStats s = this->tree_stats(f, prims_.size(), bytes, prims_.bytes());
    s.extra.emplace_back("largest leaf", std::to_string(f.max_leaf_size));
    s.extra.emplace_back("bytes per node", std::to_string(sizeof(ObbNode)) + " (the bvh's: 33)");
    char text[64];
    std::snprintf(text, sizeof text, "%.3f", aabb_sah(root_area));
    s.extra.emplace_back("SAH cost with axis-aligned boxes", text);
    return s;
}

}  // namespace thicket
