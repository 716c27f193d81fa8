#pragma once
/// `bvh8`: the production BVH. 8-wide nodes of structure-of-arrays boxes, leaves of 4-triangle
/// blocks, traversal kernels per ISA chosen at run time (docs/bvh8.md). Any PrimitiveSet: a
/// triangle set is copied into the blocks (the structure owns its triangles, no index
/// indirection); any other set keeps its primitives and leaves list ids tested one by one.
#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <ostream>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/bvh/build.h"
#include "thicket/bvh8/build.h"
#include "thicket/bvh8/bvh8_io.h"
#include "thicket/bvh8/closest_point.h"
#include "thicket/bvh8/isa.h"
#include "thicket/core/error.h"
#include "thicket/prims/primitive_set.h"
#include "thicket/prims/triangles.h"

namespace thicket {

struct Bvh8Options {
    BvhBuildOptions binary{BvhBuilder::BinnedSah, 16, 4};  ///< the binary BVH that is collapsed
    bvh8::Isa isa = bvh8::Isa::Scalar;
    uint32_t merge_below = 4;  ///< subtrees of at most this many primitives become one leaf
    bool packets = true;       ///< coherent batches go through the packet kernels
};

namespace bvh8 {
template <class P>
inline constexpr bool kIsTriangles = false;
template <TriangleTest T>
inline constexpr bool kIsTriangles<Triangles<T>> = true;
template <class P>
inline constexpr int kLeafKindOf = kLeafCallback;
template <>
inline constexpr int kLeafKindOf<Triangles<TriangleTest::Moller>> = kLeafMoller;
template <>
inline constexpr int kLeafKindOf<Triangles<TriangleTest::Watertight>> = kLeafWatertight;
}  // namespace bvh8

template <PrimitiveSet Prims>
class Bvh8 final : public AccelBase<Bvh8<Prims>> {
public:
    static constexpr int kLeafKind = bvh8::kLeafKindOf<Prims>;

    /// Builds the binary BVH with options.binary, collapses it, and picks options.isa's kernels.
    Bvh8(Prims prims, const Bvh8Options& options)
        : prims_(std::move(prims)),
          primitives_(prims_.size()),
          packets_(options.packets),
          kernels_(&bvh8::kernels_for(options.isa)) {
        std::vector<Aabb> bounds;
        std::vector<Vec3> centroids;
        primitive_boxes(
            uint32_t(prims_.size()), options.binary.threads, bounds, centroids,
            [&](uint32_t i) { return prims_.bounds(i); }, [&](uint32_t i) { return prims_.centroid(i); });
        const BvhData binary = build_bvh(
            {bounds, centroids, [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); }},
            options.binary);
        references_ = binary.prim_indices.size();
        if constexpr (bvh8::kIsTriangles<Prims>) {
            for (uint32_t i = 0; i < prims_.size(); ++i) {
                const auto v = prims_.triangle(i);
                dropped_ += Prims::degenerate({v[0], v[1], v[2]}) ? 1 : 0;
            }
            // Every block holds at least one triangle: never reallocated during the collapse. One
            // per reference, not per triangle: spatial splits (sbvh) list a triangle in several leaves.
            reserve_huge(blocks_, binary.prim_indices.size());
            std::vector<uint32_t> slivers;
            tree_ = bvh8::collapse(
                binary,
                [&](uint32_t first, uint32_t count) {
                    return emit_blocks(blocks_, binary.prim_indices.data() + first, count, &slivers);
                },
                options.merge_below);
            bvh8::validate_tree(tree_, blocks_.size());
            blocks_.shrink_to_fit();  // the reservation above is one block per triangle: 4x the need
            build_sliver_tree(std::move(slivers), options);
            prims_ = Prims();  // the blocks are the structure's only copy of the triangles
        } else {
            ids_ = binary.prim_indices;
            tree_ = bvh8::collapse(
                binary, [](uint32_t first, uint32_t count) { return bvh8::LeafPlacement{first, count}; },
                options.merge_below);
            bvh8::validate_tree(tree_, ids_.size());
        }
        ctx_ = {tree_.nodes.data(), blocks_.data(), ids_.data(), &prims_, &closest_leaf, &any_leaf};
        sliver_ctx_ = {sliver_tree_.nodes.data(), sliver_blocks_.data(), nullptr, nullptr, nullptr, nullptr};
    }
    /// Adopts a saved tree (bvh8::read_tree) after proving that it answers for `prims` as the
    /// built one would: its leaves hold the scene's own primitives (triangles bit for bit, none
    /// degenerate), every primitive that the build keeps is reachable, and every box encloses
    /// what lies below it. Throws Error naming what is wrong.
    Bvh8(Prims prims, const Bvh8Options& options, bvh8::SavedTree saved)
        : prims_(std::move(prims)),
          primitives_(prims_.size()),
          packets_(options.packets),
          tree_(std::move(saved.tree)),
          blocks_(std::move(saved.blocks)),
          ids_(std::move(saved.ids)),
          kernels_(&bvh8::kernels_for(options.isa)) {
        std::vector<Aabb> prim_bounds(primitives_);
        for (uint32_t i = 0; i < primitives_; ++i) tree_.bounds.grow(prim_bounds[i] = prims_.bounds(i));
        const ClipFunction clip = [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); };
        std::vector<bool> seen(primitives_, false);
        if constexpr (bvh8::kIsTriangles<Prims>) {
            if (!ids_.empty()) throw Error("bvh8: a triangle scene's payload lists primitive ids, not blocks");
            bvh8::for_each_leaf(tree_, [&](uint32_t first, uint32_t size) {
                for (uint32_t b = first; b < first + size; ++b) check_block(b, seen);
            });
            bvh8::check_boxes(
                tree_,
                [&](uint32_t first, uint32_t size, const std::function<void(uint32_t)>& id) {
                    for (uint32_t b = first; b < first + size; ++b)
                        for (uint32_t lane_id : blocks_[b].id)
                            if (lane_id != kNoPrim) id(lane_id);
                },
                prim_bounds, clip);
            std::vector<uint32_t> slivers;  // not saved: rebuilt as the build makes them
            for (uint32_t i = 0; i < primitives_; ++i) {
                const auto v = prims_.triangle(i);
                if (Prims::degenerate({v[0], v[1], v[2]}))
                    slivers.push_back(i);
                else if (!seen[i])
                    throw Error("bvh8: triangle " + std::to_string(i) + " is in no leaf");
            }
            dropped_ = slivers.size();
            references_ = kept_ + dropped_;  // lanes: a triangle cut by spatial splits counts per leaf
            build_sliver_tree(std::move(slivers), options);
            prims_ = Prims();  // as after a build: the blocks are the only copy
        } else {
            if (!blocks_.empty()) throw Error("bvh8: payload holds triangle blocks for a scene that is not only triangles");
            bvh8::for_each_leaf(tree_, [&](uint32_t first, uint32_t size) {
                for (uint32_t k = first; k < first + size; ++k) {
                    if (ids_[k] >= primitives_)
                        throw Error("bvh8: leaf entry " + std::to_string(k) + " names primitive " +
                                    std::to_string(ids_[k]) + " of " + std::to_string(primitives_));
                    seen[ids_[k]] = true;
                }
            });
            bvh8::check_boxes(
                tree_,
                [&](uint32_t first, uint32_t size, const std::function<void(uint32_t)>& id) {
                    for (uint32_t k = first; k < first + size; ++k) id(ids_[k]);
                },
                prim_bounds, clip);
            for (uint32_t i = 0; i < primitives_; ++i)
                if (!seen[i]) throw Error("bvh8: primitive " + std::to_string(i) + " is in no leaf");
            references_ = ids_.size();
        }
        ctx_ = {tree_.nodes.data(), blocks_.data(), ids_.data(), &prims_, &closest_leaf, &any_leaf};
        sliver_ctx_ = {sliver_tree_.nodes.data(), sliver_blocks_.data(), nullptr, nullptr, nullptr, nullptr};
    }
    Bvh8(const Bvh8&) = delete;  // ctx_ points into this object
    Bvh8& operator=(const Bvh8&) = delete;

    Aabb bounds() const override { return tree_.bounds; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        if (tree_.nodes.empty()) return miss_for(ray);
        if constexpr (std::is_same_v<C, RayCounters>)
            return kernels_->closest[kLeafKind][1](ctx_, ray, &counters);
        else
            return kernels_->closest[kLeafKind][0](ctx_, ray, nullptr);
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        if (tree_.nodes.empty()) return false;
        if constexpr (std::is_same_v<C, RayCounters>)
            return kernels_->any[kLeafKind][1](ctx_, ray, &counters);
        else
            return kernels_->any[kLeafKind][0](ctx_, ray, nullptr);
    }

    /// The closest point of the triangles to p through the per-ISA point traversal, degenerate
    /// triangles included (their points are on the surface; rays never hit them); shapes: Error.
    NearestPoint closest_point(const Vec3& p) const override {
        if constexpr (bvh8::kIsTriangles<Prims>)
            return bvh8::closest_point(*kernels_,
                                       {tree_.nodes.empty() ? nullptr : &ctx_,
                                        sliver_tree_.nodes.empty() ? nullptr : &sliver_ctx_},
                                       p);
        else
            return Accel::closest_point(p);  // shapes: refused with the reason
    }
    bool has_closest_point() const override { return bvh8::kIsTriangles<Prims>; }

    using Accel::all_hits;  // the batch forms stay visible next to the per-ray overrides
    using Accel::count_hits;

    /// Every crossing from one traversal that prunes nothing (triangle leaves): all the hits,
    /// sorted and merged by Accel::all_hits' rule (merge_crossings), which gives the crossings
    /// stepping from one to the next would, without a traversal per crossing. Shapes: stepping.
    void all_hits(const Ray& ray, std::vector<Hit>& out) const override {
        if constexpr (bvh8::kIsTriangles<Prims>)
            every_hit(ray, [&](std::span<Hit> hits) { merge_crossings(hits, &out); });
        else
            Accel::all_hits(ray, out);
    }
    uint32_t count_hits(const Ray& ray) const override {
        if constexpr (bvh8::kIsTriangles<Prims>) {
            uint32_t count = 0;
            every_hit(ray, [&](std::span<Hit> hits) { count = uint32_t(merge_crossings(hits, nullptr)); });
            return count;
        } else {
            return Accel::count_hits(ray);
        }
    }

    AccelStats stats() const override {
        AccelStats s = this->base_stats();
        s.primitives = primitives_;
        s.nodes = tree_.nodes.size() + tree_.leaves;  // AccelStats counts leaves as nodes
        s.leaves = tree_.leaves;
        s.max_depth = tree_.max_depth;
        s.bytes = (tree_.nodes.size() + sliver_tree_.nodes.size()) * sizeof(bvh8::Node) + ids_.size() * sizeof(uint32_t);
        s.primitive_bytes = bvh8::kIsTriangles<Prims> ? (blocks_.size() + sliver_blocks_.size()) * sizeof(bvh8::Tri4)
                                                      : prims_.bytes();
        s.sah_cost = tree_.sah_cost;
        s.extra.emplace_back("isa", kernels_->isa);
        s.extra.emplace_back("8-wide nodes", std::to_string(tree_.nodes.size()));
        s.extra.emplace_back("Embree SAH", std::to_string(tree_.embree_sah_cost));
        if constexpr (bvh8::kIsTriangles<Prims>) {
            const size_t lanes = blocks_.size() * 4;
            s.extra.emplace_back("4-triangle blocks", std::to_string(blocks_.size()) + " (" +
                                                          std::to_string(lanes ? 100 * kept_ / lanes : 0) +
                                                          "% of lanes used)");
            s.extra.emplace_back("degenerate dropped", std::to_string(dropped_));
        }
        // More references than primitives: spatial splits (builder=sbvh) list some in several leaves.
        s.extra.emplace_back("references", reference_figure(references_, primitives_));
        return s;
    }

    void save(std::ostream& out) const override { bvh8::write_tree(out, tree_, blocks_, ids_); }

    const bvh8::Tree& tree() const { return tree_; }
    const bvh8::KernelTable& kernels() const { return *kernels_; }
    const AlignedVector<bvh8::Tri4, 64>& blocks() const { return blocks_; }
    /// The degenerate triangles' blocks, searched by closest_point() only.
    const AlignedVector<bvh8::Tri4, 64>& sliver_blocks() const { return sliver_blocks_; }

protected:
    /// Coherent batches: each 16 consecutive rays that share a direction octant (and have no zero
    /// direction component) go through the packet kernel; others, and incoherent batches, ray by ray.
    void intersect_chunk(std::span<const Ray> rays, std::span<Hit> hits, bool coherent) const override {
        if (!coherent || !packets_ || tree_.nodes.empty()) return Accel::intersect_chunk(rays, hits, coherent);
        for (size_t begin = 0; begin < rays.size(); begin += bvh8::kPacketSize) {
            const uint32_t count = uint32_t(std::min<size_t>(bvh8::kPacketSize, rays.size() - begin));
            if (count > 1 && packet_eligible(&rays[begin], count)) {
                kernels_->packet_closest[kLeafKind](ctx_, &rays[begin], count, &hits[begin]);
            } else {
                NoCounters none;
                for (size_t i = begin; i < begin + count; ++i) hits[i] = closest(rays[i], none);
            }
        }
    }

private:
    /// Calls f(hits) with every hit of the ray (AllHitsFn's), in a buffer on the stack when they
    /// are few.
    template <class F>
    void every_hit(const Ray& ray, F&& f) const {
        if (tree_.nodes.empty()) return;
        Hit few[64];
        const uint32_t n = kernels_->all_hits[kLeafKind](ctx_, ray, few, 64);
        if (n <= 64) return f(std::span<Hit>(few, n));
        std::vector<Hit> many(n);
        kernels_->all_hits[kLeafKind](ctx_, ray, many.data(), n);
        f(std::span<Hit>(many));
    }

    /// The packet kernels' precondition: one octant, finite 1/dir on every axis (the kernels
    /// compute 1/dir the same way).
    static bool packet_eligible(const Ray* rays, uint32_t count) {
        auto octant = [](const Vec3& d, bool& finite) {
            const float inv[3] = {1.0f / d.x, 1.0f / d.y, 1.0f / d.z};
            int o = 0;
            for (int a = 0; a < 3; ++a) {
                finite = finite && std::isfinite(inv[a]);
                o |= int(std::signbit(inv[a])) << a;
            }
            return o;
        };
        bool finite = true;
        const int first = octant(rays[0].dir, finite);
        for (uint32_t k = 1; k < count && finite; ++k)
            if (octant(rays[k].dir, finite) != first) return false;
        return finite;
    }

    /// Copies a leaf's triangles into 4-lane blocks of `out`. With `slivers`, degenerate ones are
    /// left out (they are never hit: Triangles::plausible) and their ids appended there instead;
    /// without, every triangle is kept (the sliver tree).
    bvh8::LeafPlacement emit_blocks(AlignedVector<bvh8::Tri4, 64>& out, const uint32_t* prims, uint32_t count,
                                    std::vector<uint32_t>* slivers) {
        bvh8::LeafPlacement p{uint32_t(out.size()), 0};
        uint32_t lane = 4;
        for (uint32_t k = 0; k < count; ++k) {
            // A merged subtree (leaf-merge) may hold both parts of a triangle that a spatial split
            // cut: one lane is enough. Only a tree with more references than triangles can.
            if (references_ > primitives_ && std::find(prims, prims + k, prims[k]) != prims + k) continue;
            const auto v = prims_.triangle(prims[k]);
            if (slivers && Prims::degenerate({v[0], v[1], v[2]})) {
                slivers->push_back(prims[k]);
                continue;
            }
            if (lane == 4) {
                out.emplace_back();
                bvh8::Tri4& b = out.back();
                for (auto& vertex : b.v)
                    for (auto& axis : vertex)
                        for (float& x : axis) x = 0.0f;
                for (uint32_t& id : b.id) id = kNoPrim;
                lane = 0;
                ++p.size;
            }
            bvh8::Tri4& b = out.back();
            for (int vertex = 0; vertex < 3; ++vertex)
                for (int a = 0; a < 3; ++a) b.v[vertex][a][lane] = v[size_t(vertex)][a];
            b.id[lane] = prims[k];
            ++lane;
            if (slivers) ++kept_;
        }
        return p;
    }

    /// Degenerate triangles have no interior for rays, but their points are on the surface and
    /// brute force answers them as closest points: they get a tree of their own (usually empty or
    /// tiny), which only the closest-point query searches, so the ray kernels never see them.
    /// Spatial splits may list a sliver in several leaves: each is kept once, and the sliver tree
    /// is an object-partition one (builder=sbvh falls back to binned SAH for it).
    void build_sliver_tree(std::vector<uint32_t> slivers, const Bvh8Options& options) {
        std::sort(slivers.begin(), slivers.end());
        slivers.erase(std::unique(slivers.begin(), slivers.end()), slivers.end());
        if (slivers.empty()) return;
        std::vector<Aabb> bounds;
        std::vector<Vec3> centroids;
        primitive_boxes(
            uint32_t(slivers.size()), options.binary.threads, bounds, centroids,
            [&](uint32_t i) { return prims_.bounds(slivers[i]); }, [&](uint32_t i) { return prims_.centroid(slivers[i]); });
        BvhBuildOptions binary_options = options.binary;
        if (binary_options.builder == BvhBuilder::Sbvh) binary_options.builder = BvhBuilder::BinnedSah;
        const BvhData binary = build_bvh({bounds, centroids}, binary_options);
        std::vector<uint32_t> ids;
        sliver_tree_ = bvh8::collapse(
            binary,
            [&](uint32_t first, uint32_t count) {
                ids.clear();
                for (uint32_t k = 0; k < count; ++k) ids.push_back(slivers[binary.prim_indices[first + k]]);
                return emit_blocks(sliver_blocks_, ids.data(), count, nullptr);
            },
            options.merge_below);
        bvh8::validate_tree(sliver_tree_, sliver_blocks_.size());
    }

    /// A loaded block: each lane either the scene's non-degenerate triangle `id` bit for bit, or
    /// kNoPrim with all-zero vertices (never hit). Marks the triangles seen; counts kept_.
    void check_block(uint32_t index, std::vector<bool>& seen) {
        const bvh8::Tri4& b = blocks_[index];
        for (int lane = 0; lane < 4; ++lane) {
            const std::string where = "bvh8: block " + std::to_string(index) + " lane " + std::to_string(lane);
            if (b.id[lane] == kNoPrim) {
                for (int vertex = 0; vertex < 3; ++vertex)
                    for (int a = 0; a < 3; ++a)
                        if (b.v[vertex][a][lane] != 0.0f) throw Error(where + ": an empty lane with a vertex");
                continue;
            }
            if (b.id[lane] >= primitives_)
                throw Error(where + " names triangle " + std::to_string(b.id[lane]) + " of " + std::to_string(primitives_));
            const auto v = prims_.triangle(b.id[lane]);
            if (Prims::degenerate({v[0], v[1], v[2]}))
                throw Error(where + " holds degenerate triangle " + std::to_string(b.id[lane]));
            for (int vertex = 0; vertex < 3; ++vertex)
                for (int a = 0; a < 3; ++a)
                    if (std::bit_cast<uint32_t>(b.v[vertex][a][lane]) != std::bit_cast<uint32_t>(v[size_t(vertex)][a]))
                        throw Error(where + ": triangle " + std::to_string(b.id[lane]) + " differs from the scene's");
            seen[b.id[lane]] = true;
            ++kept_;
        }
    }
    static bool closest_leaf(const void* prims, const uint32_t* ids, uint32_t count, const Ray& ray, Hit& hit) {
        const Prims& p = *static_cast<const Prims*>(prims);
        bool found = false;
        for (uint32_t k = 0; k < count; ++k) found = p.intersect(ids[k], ray, hit) || found;
        return found;
    }
    static bool any_leaf(const void* prims, const uint32_t* ids, uint32_t count, const Ray& ray) {
        const Prims& p = *static_cast<const Prims*>(prims);
        for (uint32_t k = 0; k < count; ++k)
            if (p.occludes(ids[k], ray)) return true;
        return false;
    }

    Prims prims_;
    size_t primitives_ = 0;
    size_t kept_ = 0;        ///< triangle lanes filled (a triangle once per leaf listing it)
    size_t dropped_ = 0;     ///< degenerate triangles, never stored
    size_t references_ = 0;  ///< entries of the binary tree's leaves
    bool packets_ = true;
    bvh8::Tree tree_;
    AlignedVector<bvh8::Tri4, 64> blocks_;
    std::vector<uint32_t> ids_;
    const bvh8::KernelTable* kernels_;
    bvh8::TraceContext ctx_;
    bvh8::Tree sliver_tree_;                       ///< degenerate triangles, for closest points only
    AlignedVector<bvh8::Tri4, 64> sliver_blocks_;
    bvh8::TraceContext sliver_ctx_;
};

}  // namespace thicket
