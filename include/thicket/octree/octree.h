#pragma once
/// The adaptive octree (Glassner 1984) over any primitive set, with the parametric traversal of
/// Revelles et al. (2000) or the lecture's restart traversal. Usable directly (no virtual call)
/// or through the Accel interface.
#include <cstdio>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/octree/draw.h"
#include "thicket/octree/build.h"
#include "thicket/octree/traversal.h"

namespace thicket {

template <PrimitiveSet Prims>
class Octree final : public AccelBase<Octree<Prims>> {
public:
    Octree(Prims prims, const OctreeBuildOptions& options, OctreeTraversal traversal = OctreeTraversal::Parametric)
        : prims_(std::move(prims)), traversal_(traversal) {
        std::vector<Aabb> bounds(prims_.size());
        for (uint32_t i = 0; i < prims_.size(); ++i) {
            bounds[i] = prims_.bounds(i);
            bounds_.grow(bounds[i]);
        }
        const OctreeClip clip = [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); };
        data_ = build_octree(bounds, clip, options);
    }

    /// Adopts a saved (e.g. loaded) tree after proving it lists every primitive wherever the
    /// builder would (validate_octree, validate_octree_coverage).
    Octree(Prims prims, OctreeData data, OctreeTraversal traversal)
        : prims_(std::move(prims)), data_(std::move(data)), traversal_(traversal) {
        validate_octree(data_, prims_.size());
        std::vector<Aabb> bounds(prims_.size());
        for (uint32_t i = 0; i < prims_.size(); ++i) {
            bounds[i] = prims_.bounds(i);
            bounds_.grow(bounds[i]);
        }
        const OctreeClip clip = [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); };
        validate_octree_coverage(data_, bounds, clip);
    }

    Aabb bounds() const override { return bounds_; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        return closest_hit<octree_detail::Query>(data_, prims_, ray, counters, traversal_);
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        return any_hit<octree_detail::Query>(data_, prims_, ray, counters, traversal_);
    }

    AccelStats stats() const override {
        const OctreeFigures f = octree_figures(data_);
        AccelStats s = this->tree_stats(
            f, prims_.size(), data_.nodes.size() * sizeof(OctreeNode) + data_.refs.size() * sizeof(uint32_t),
            prims_.bytes());
        char per_prim[32];
        std::snprintf(per_prim, sizeof per_prim, "%.2f", prims_.size() ? double(f.references) / prims_.size() : 0.0);
        s.extra.emplace_back("empty leaves", std::to_string(f.empty_leaves));
        s.extra.emplace_back("references", std::to_string(f.references) + " (" + per_prim + " per primitive)");
        s.extra.emplace_back("largest leaf", std::to_string(f.max_leaf_size));
        return s;
    }

    void save(std::ostream& out) const override { write_octree(out, data_); }

    const OctreeData& data() const { return data_; }
    const Prims& primitives() const { return prims_; }

private:
    Prims prims_;
    Aabb bounds_;
    OctreeData data_;
    OctreeTraversal traversal_;
};

}  // namespace thicket
