#pragma once
/// The BVH in double precision (`bvh:precision=double`): the tree is built by the float builders
/// over each triangle's box rounded outward to float, then every node gets a double box, the
/// union of its triangles' double boxes (so the boxes are exact in double whatever float did),
/// and rays are traced in double against those boxes and the double triangles, by the float
/// BVH's own traversals (bvh/traversal.h over BvhDataD).
#include <cstdint>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/bvh/build.h"
#include "thicket/bvh/traversal.h"
#include "thicket/prims/triangles.h"

namespace thicket {

template <TriangleTest Test>
class BvhD final : public AccelBase<BvhD<Test>> {
    friend class AccelBase<BvhD<Test>>;

public:
    static constexpr bool kDoublePrecision = true;

    /// Builds over `prims` with the float builders (options.builder etc.), traced in `traversal`
    /// order, as the float BVH is.
    BvhD(TrianglesD<Test> prims, const BvhBuildOptions& options, BvhTraversal traversal)
        : prims_(std::move(prims)), traversal_(traversal) {
        std::vector<Aabb> bounds;
        std::vector<Vec3> centroids;
        primitive_boxes(
            uint32_t(prims_.size()), options.threads, bounds, centroids,
            [&](uint32_t i) { return outward_float_box(prims_.bounds(i)); },
            [&](uint32_t i) { return prims_.centroid(i).to_float(); });
        // No clip function: spatial splits (sbvh) cut the float boxes, which is conservative.
        BvhData tree = build_bvh({bounds, centroids, {}}, options);
        figures_ = bvh_figures(tree);
        data_.nodes.resize(tree.nodes_used);
        data_.nodes_used = tree.nodes_used;
        if (tree.nodes_used) fill_boxes(tree, 0);
        data_.prim_indices = std::move(tree.prim_indices);
        data_.child_order = std::move(tree.child_order);
    }

    Aabb bounds() const override { return data_.nodes_used ? outward_float_box(data_.nodes[0].bounds()) : Aabb{}; }

    AccelStats stats() const override {
        AccelStats s = this->tree_stats(figures_, prims_.size(),
                                        size_t(data_.nodes_used) * (sizeof(BvhNodeD) + 1) +
                                            data_.prim_indices.size() * sizeof(uint32_t),
                                        prims_.bytes());
        s.extra.emplace_back("precision", "double (nodes, triangles and rays)");
        s.extra.emplace_back("largest leaf", std::to_string(figures_.max_leaf_size));
        s.extra.emplace_back("references", reference_figure(data_.prim_indices.size(), prims_.size()));
        return s;
    }

private:
    /// Node n of the float tree again with its double box, from its subtree (children come after
    /// parents, depth < kMaxDepth).
    AabbD fill_boxes(const BvhData& tree, uint32_t n) {
        const BvhNode& f = tree.nodes[n];
        AabbD box;
        if (f.is_leaf()) {
            for (uint32_t i = f.leftFirst; i < f.leftFirst + f.count; ++i) box.grow(prims_.bounds(tree.prim_indices[i]));
        } else {
            box.grow(fill_boxes(tree, f.leftFirst));
            box.grow(fill_boxes(tree, f.leftFirst + 1));
        }
        data_.nodes[n] = {box.min, f.leftFirst, box.max, f.count};
        return box;
    }

    template <class C>
    HitD closest(const RayD& ray, C& counters) const {
        HitD hit = miss_for(ray);
        bvh_detail::QueryOver<false, TrianglesD<Test>, C, BvhDataD>(data_, prims_, ray, hit, counters).run(traversal_);
        return hit;
    }
    template <class C>
    bool any(const RayD& ray, C& counters) const {
        HitD unused = miss_for(ray);
        return bvh_detail::QueryOver<true, TrianglesD<Test>, C, BvhDataD>(data_, prims_, ray, unused, counters).run(traversal_);
    }

    TrianglesD<Test> prims_;
    BvhDataD data_;
    BvhFigures figures_;  ///< of the float boxes the builder chose
    BvhTraversal traversal_;
};

}  // namespace thicket
