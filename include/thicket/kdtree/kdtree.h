#pragma once
/// The kD-tree over any primitive set: 8-byte nodes, a primitive index list, SAH or median
/// builds with perfect splits, kd-restart or stack traversal. Usable directly (no virtual call)
/// or through the Accel interface.
#include <cstdio>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/kdtree/draw.h"
#include "thicket/kdtree/build.h"
#include "thicket/kdtree/traversal.h"

namespace thicket {

template <PrimitiveSet Prims>
class KdTree final : public AccelBase<KdTree<Prims>> {
public:
    /// Builds over `prims`.
    KdTree(Prims prims, const KdBuildOptions& options, KdTraversal traversal = KdTraversal::Stack)
        : prims_(std::move(prims)), options_(options), traversal_(traversal) {
        std::vector<Aabb> bounds(prims_.size());
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds[i] = prims_.bounds(i);
        const KdBuildInput input{bounds, [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); }};
        data_ = build_kdtree(input, options);
    }

    /// Adopts an already built (e.g. loaded) tree after checking it fits `prims`.
    KdTree(Prims prims, KdTreeData data, const KdBuildOptions& options, KdTraversal traversal)
        : prims_(std::move(prims)), data_(std::move(data)), options_(options), traversal_(traversal) {
        validate_kdtree(data_, prims_.size());
        std::vector<Aabb> bounds(prims_.size());
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds[i] = prims_.bounds(i);
        const KdBuildInput input{bounds, [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); }};
        validate_kdtree_coverage(data_, input);
    }

    Aabb bounds() const override { return data_.nodes.empty() ? Aabb{} : data_.bounds; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        return closest_hit<kd_detail::KdQuery>(data_, prims_, ray, counters, traversal_);
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        return any_hit<kd_detail::KdQuery>(data_, prims_, ray, counters, traversal_);
    }

    AccelStats stats() const override {
        const KdFigures f = kdtree_figures(data_, options_.cost);
        AccelStats s = this->tree_stats(
            f, prims_.size(), data_.nodes.size() * sizeof(KdNode) + data_.prim_indices.size() * sizeof(uint32_t),
            prims_.bytes());
        const double refs = prims_.size() ? double(f.references) / double(prims_.size()) : 0.0;
        auto fixed = [](double v, int digits) {
            std::string out(32, '\0');
            out.resize(size_t(std::snprintf(out.data(), out.size(), "%.*f", digits, v)));
            return out;
        };
        s.extra.emplace_back("empty leaves", std::to_string(f.empty_leaves));
        s.extra.emplace_back("references", std::to_string(f.references) + " (" + fixed(refs, 2) + " per primitive)");
        s.extra.emplace_back("largest leaf", std::to_string(f.max_leaf_size));
        s.extra.emplace_back("depth limit", std::to_string(kd_max_depth(options_, prims_.size())));
        s.extra.emplace_back("builder SAH cost", fixed(f.builder_cost, 3) + " (K_T = " + fixed(options_.cost.traversal, 2) +
                                                     ", K_I = " + fixed(options_.cost.intersection, 2) + ")");
        return s;
    }

    void save(std::ostream& out) const override { write_kdtree(out, data_); }

    const KdTreeData& data() const { return data_; }
    const Prims& primitives() const { return prims_; }

private:
    Prims prims_;
    KdTreeData data_;
    KdBuildOptions options_;
    KdTraversal traversal_;
};

}  // namespace thicket
