#pragma once
/// The bounding interval hierarchy (Wächter & Keller 2006) over any primitive set: 12-byte nodes
/// with two clip planes, built by the global heuristic, traversed kd-tree style. Usable directly
/// (no virtual call) or through the Accel interface.
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/bih/draw.h"
#include "thicket/bih/build.h"
#include "thicket/bih/traversal.h"

namespace thicket {

template <PrimitiveSet Prims>
class Bih final : public AccelBase<Bih<Prims>> {
public:
    /// Builds over `prims`.
    Bih(Prims prims, const BihBuildOptions& options) : prims_(std::move(prims)) {
        std::vector<Aabb> bounds(prims_.size());
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds[i] = prims_.bounds(i);
        data_ = build_bih(bounds, options);
    }

    /// Adopts an already built (e.g. loaded) BIH after checking it fits `prims`.
    Bih(Prims prims, BihData data) : prims_(std::move(prims)), data_(std::move(data)) {
        validate_bih(data_, prims_.size());
        std::vector<Aabb> bounds(prims_.size());
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds[i] = prims_.bounds(i);
        validate_bih_bounds(data_, bounds);
    }

    Aabb bounds() const override { return data_.bounds; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        return closest_hit<bih_detail::Query>(data_, prims_, ray, counters);
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        return any_hit<bih_detail::Query>(data_, prims_, ray, counters);
    }

    AccelStats stats() const override {
        const BihFigures f = bih_figures(data_);
        AccelStats s = this->tree_stats(
            f, prims_.size(), data_.nodes.size() * sizeof(BihNode) + data_.prim_indices.size() * sizeof(uint32_t),
            prims_.bytes());
        s.extra.emplace_back("node size", std::to_string(sizeof(BihNode)) + " bytes");
        s.extra.emplace_back("empty leaves", std::to_string(f.empty_leaves));
        s.extra.emplace_back("largest leaf", std::to_string(f.max_leaf_size));
        return s;
    }

    void save(std::ostream& out) const override { write_bih(out, data_); }

    const BihData& data() const { return data_; }
    const Prims& primitives() const { return prims_; }

private:
    Prims prims_;
    BihData data_;
};

}  // namespace thicket
