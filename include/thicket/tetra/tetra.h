#pragma once
/// Ray traversal through a constrained tetrahedralization (Lagae & Dutré 2008) over any
/// primitive set: TetGen's mesh of the triangles it accepts, a BVH over the rest (shapes and
/// refused triangles); a query answers the closer of the two.
#include <cstdio>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/tetra/draw.h"
#include "thicket/bvh/build.h"
#include "thicket/bvh/traversal.h"
#include "thicket/tetra/build.h"
#include "thicket/tetra/traversal.h"

namespace thicket {

namespace tetra_detail {

/// The primitives at `ids` as a primitive set of their own, answering with the scene's ids.
template <PrimitiveSet Prims>
struct Subset {
    const Prims* prims;
    const std::vector<uint32_t>* ids;
    size_t size() const { return ids->size(); }
    size_t bytes() const { return 0; }
    Aabb bounds(uint32_t i) const { return prims->bounds((*ids)[i]); }
    Vec3 centroid(uint32_t i) const { return prims->centroid((*ids)[i]); }
    bool intersect(uint32_t i, const Ray& r, Hit& h) const { return prims->intersect((*ids)[i], r, h); }
    bool occludes(uint32_t i, const Ray& r) const { return prims->occludes((*ids)[i], r); }
};

/// What the build reads of a primitive set: triangles where the set has them.
template <PrimitiveSet Prims>
TetraInput tetra_input(const Prims& prims) {
    TetraInput in;
    in.count = prims.size();
    in.bounds = [&prims](uint32_t i) { return prims.bounds(i); };
    if constexpr (kHasTriangles<Prims>) {
        in.is_triangle = [](uint32_t) { return true; };
        in.triangle = [&prims](uint32_t i) { return prims.triangle(i); };
    } else if constexpr (requires(const Prims& p, uint32_t i) { p.triangle_of(i); }) {
        in.is_triangle = [&prims](uint32_t i) { return prims.triangle_of(i).has_value(); };
        in.triangle = [&prims](uint32_t i) { return *prims.triangle_of(i); };
    } else {
        in.is_triangle = [](uint32_t) { return false; };
        in.triangle = [](uint32_t) { return std::array<Vec3, 3>{}; };
    }
    return in;
}

/// The counting policy the fallback BVH is walked with: counts go to `c`; for a recorder, the
/// primitives tested are listed under their scene ids, and the BVH's node ids are left out, where
/// they would read as tetrahedra (the steps name tetrahedra by their index in the mesh).
template <class C>
struct FallbackCounters {
    C& c;
    const std::vector<uint32_t>& ids;  ///< the fallback primitives: the BVH's indices are positions here
    void node() { c.node(); }
    void prim() { c.prim(); }
    void record_node(uint32_t, float) {}
    void record_skip(uint32_t, float) {}
    void record_prim(uint32_t i, float t) { c.record_prim(ids[i], t); }
};

}  // namespace tetra_detail

template <PrimitiveSet Prims>
class Tetra final : public AccelBase<Tetra<Prims>> {
public:
    /// Tetrahedralizes `prims` (see build_tetra).
    Tetra(Prims prims, const TetraBuildOptions& options)
        : prims_(std::move(prims)), data_(build_tetra(tetra_detail::tetra_input(prims_), options)) {
        init();
    }
    /// Adopts an already built (e.g. loaded) structure after proving it fits `prims`: structure,
    /// then the geometry the walk relies on (validate_tetra_geometry).
    Tetra(Prims prims, TetraData data) : prims_(std::move(prims)), data_(std::move(data)) {
        validate_tetra(data_, prims_.size());
        validate_tetra_geometry(data_, tetra_detail::tetra_input(prims_));
        init();
    }

    Aabb bounds() const override {
        Aabb b;
        for (uint32_t i = 0; i < prims_.size(); ++i) b.grow(prims_.bounds(i));
        return b;
    }

    /// Both walks tell a recorder each tetrahedron entered and each primitive tested (traversal.h).
    static constexpr bool kRecordsSteps = true;
    static constexpr bool kRecordsAnyHitSteps = true;

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        Hit hit = miss_for(ray);
        if (!data_.fallback.empty()) {
            auto&& fallback = fallback_counters(counters);
            hit = closest_hit<bvh_detail::Query>(data_.fallback_bvh, subset_, ray, fallback,
                                                 BvhTraversal::OrderedDistance);
        }
        tetra_detail::walk<false>(
            data_.mesh, prims_.size(), ray, hit, counters, [&](uint32_t p) { return prims_.intersect(p, ray, hit); },
            [&](Mailbox& mailbox) {
                for (uint32_t p : meshed_)
                    if (mailbox.first_visit(p)) {
                        counters.prim();
                        prims_.intersect(p, ray, hit);
                        if constexpr (RecordsSteps<C>) counters.record_prim(p, hit.t);
                    }
                return false;
            });
        return hit;
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        if (!data_.fallback.empty()) {
            auto&& fallback = fallback_counters(counters);
            if (any_hit<bvh_detail::Query>(data_.fallback_bvh, subset_, ray, fallback, BvhTraversal::OrderedDistance))
                return true;
        }
        const Hit none = miss_for(ray);
        return tetra_detail::walk<true>(
            data_.mesh, prims_.size(), ray, none, counters, [&](uint32_t p) { return prims_.occludes(p, ray); },
            [&](Mailbox& mailbox) {
                for (uint32_t p : meshed_)
                    if (mailbox.first_visit(p)) {
                        counters.prim();
                        const bool found = prims_.occludes(p, ray);
                        if constexpr (RecordsSteps<C>) counters.record_prim(p, ray.tmax);
                        if (found) return true;
                    }
                return false;
            });
    }

    AccelStats stats() const override;

    void save(std::ostream& out) const override { write_tetra(out, data_); }

    const TetraData& data() const { return data_; }

private:
    /// A recorder is wrapped for the fallback BVH (FallbackCounters); other policies pass as they are.
    template <class C>
    decltype(auto) fallback_counters(C& counters) const {
        if constexpr (RecordsSteps<C>)
            return tetra_detail::FallbackCounters<C>{counters, data_.fallback};
        else
            return (counters);
    }

    void init() {
        subset_ = {&prims_, &data_.fallback};
        std::vector<uint8_t> in_fallback(prims_.size(), 0);
        for (uint32_t p : data_.fallback) in_fallback[p] = 1;
        for (uint32_t p = 0; p < prims_.size(); ++p)
            if (!in_fallback[p]) meshed_.push_back(p);
    }

    Prims prims_;
    TetraData data_;
    tetra_detail::Subset<Prims> subset_{};
    std::vector<uint32_t> meshed_;  ///< the primitives the mesh holds (a stalled walk tests them all)
};

template <PrimitiveSet Prims>
AccelStats Tetra<Prims>::stats() const {
    const TetraMesh& m = data_.mesh;
    const TetraReport& r = data_.report;
    const size_t fallback_bytes = size_t(data_.fallback_bvh.nodes_used) * (sizeof(BvhNode) + 1) +
                                  data_.fallback_bvh.prim_indices.size() * sizeof(uint32_t) +
                                  data_.fallback.size() * sizeof(uint32_t);
    AccelStats s = this->base_stats();
    s.primitives = prims_.size();
    s.nodes = m.tet_count() + data_.fallback_bvh.nodes_used;
    s.leaves = m.tet_count();
    s.bytes = m.bytes() + fallback_bytes;
    s.primitive_bytes = prims_.bytes();
    s.extra.emplace_back(kSahUndefinedKey, "a tetrahedral mesh has no box hierarchy to weigh");
    char text[160];
    s.extra.emplace_back("tetrahedra", std::to_string(m.tet_count()));
    s.extra.emplace_back("triangles meshed", std::to_string(r.meshed_triangles) + " of " +
                                                 std::to_string(r.input_triangles) + " triangles");
    std::snprintf(text, sizeof text, "%.2f", r.meshed_triangles ? double(m.tet_count()) / r.meshed_triangles : 0.0);
    s.extra.emplace_back("tetrahedra per meshed triangle", text);
    s.extra.emplace_back("Steiner points", std::to_string(r.steiner_points));
    std::snprintf(text, sizeof text, "%.1f", prims_.size() ? double(s.bytes) / double(prims_.size()) : 0.0);
    s.extra.emplace_back("bytes per primitive", text);
    s.extra.emplace_back("fallback primitives", std::to_string(data_.fallback.size()) + " (in a bvh)");
    std::snprintf(text, sizeof text, "%.1f ms in %u run(s)", r.tetgen_ms, r.tetgen_runs);
    s.extra.emplace_back("TetGen", text);
    if (!r.outcome.empty()) s.extra.emplace_back(kLimitedKey, r.outcome);
    return s;
}

}  // namespace thicket
