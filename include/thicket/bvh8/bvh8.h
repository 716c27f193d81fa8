#pragma once
/// `bvh8`: the production BVH. 8-wide nodes of structure-of-arrays boxes, leaves of 4-triangle
/// blocks, traversal kernels per ISA chosen at run time (docs/bvh8.md). Any PrimitiveSet: a
/// triangle set is copied into the blocks (the structure owns its triangles, no index
/// indirection); any other set keeps its primitives and leaves list ids tested one by one.
/// This class composes the pieces, one concept per file (docs/bvh8.md, "Files"): node.h (layout
/// and kernel interface), build.h (binary build and collapse), blocks.h (4-triangle blocks),
/// bvh8_io.h (saving, loading and its proofs),
/// stats.h, and the queries' baseline sides: isa.h (the kernels' choice), packets.h,
/// closest_point.h.
#include <algorithm>
#include <atomic>
#include <ostream>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/accel/refit.h"
#include "thicket/bvh/build.h"
#include "thicket/bvh8/blocks.h"
#include "thicket/bvh8/build.h"
#include "thicket/bvh8/compress.h"
#include "thicket/bvh8/draw.h"
#include "thicket/bvh8/foreign_tree.h"
#include "thicket/bvh8/bvh8_io.h"
#include "thicket/bvh8/closest_point.h"
#include "thicket/bvh8/isa.h"
#include "thicket/bvh8/packets.h"
#include "thicket/bvh8/refit.h"
#include "thicket/bvh8/stats.h"
#include "thicket/core/huge_pages.h"
#include "thicket/prims/primitive_set.h"
#include "thicket/prims/triangles.h"

namespace thicket {

struct Bvh8Options {
    /// The binary BVH that is collapsed: leaves weighed in 4-triangle blocks (sah_block 4).
    BvhBuildOptions binary{BvhBuilder::BinnedSah, 16, 4, 4};
    Isa isa = Isa::Scalar;
    uint32_t merge_below = 4;  ///< subtrees of at most this many primitives become one leaf
    bool packets = true;       ///< coherent batches go through the packet kernels
    bool compressed = false;   ///< nodes=compressed: QNodes (96 bytes) instead of Nodes (256)
    /// tree=embree-*: Embree's builder writes the tree (bvh8/foreign_tree.h); `binary` unused.
    bvh8::TreeSource tree = bvh8::TreeSource::Thicket;
};

namespace bvh8 {
/// How the kernels test a set's leaves: 4-triangle blocks for the two triangle sets (the
/// structure's own copy of them), a callback through the set's ids for any other.
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
    /// The leaves are 4-triangle blocks; otherwise primitive ids into prims_.
    static constexpr bool kBlocks = kLeafKind != bvh8::kLeafCallback;

    /// Builds the binary BVH with options.binary and collapses it (or has the foreign builder
    /// options.tree names write the tree), and picks options.isa's kernels.
    Bvh8(Prims prims, const Bvh8Options& options)
        : prims_(std::move(prims)),
          primitives_(prims_.size()),
          packets_(options.packets),
          kernels_(&bvh8::kernels_for(options.isa)) {
        if (options.tree == bvh8::TreeSource::Thicket) {
            const BvhData binary = bvh8::build_binary(prims_, options.binary);
            adopt_build(binary.prim_indices, bvh8::block_count(binary, options.merge_below),
                        [&](const bvh8::LeafEmitter& emit) { return bvh8::collapse(binary, emit, options.merge_below); });
        } else {
            std::vector<Aabb> prim_bounds(primitives_);
            for (uint32_t i = 0; i < primitives_; ++i) prim_bounds[i] = prims_.bounds(i);
            const ClipFunction clip = [this](uint32_t i, const Aabb& box) { return clipped_bounds(prims_, i, box); };
            const bvh8::WideTree wide =
                bvh8::build_foreign_tree({prim_bounds, clip, options.tree, options.binary.threads});
            adopt_build(wide.prims, bvh8::block_count(wide),
                        [&](const bvh8::LeafEmitter& emit) { return bvh8::write_wide_tree(wide, emit); });
        }
        adopt_layout(options.compressed);
        set_contexts();
    }
    /// Adopts a saved tree (bvh8::read_tree) after proving that it answers for `prims` as the
    /// built one would: its leaves hold the scene's own primitives (triangles bit for bit), every
    /// primitive is reachable, and every box encloses
    /// what lies below it (bvh8::prove_blocks, bvh8::prove_ids). Throws Error naming what is wrong.
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
        if constexpr (kBlocks) {
            kept_ = bvh8::prove_blocks(tree_, blocks_, ids_, prims_, prim_bounds, clip);
            references_ = kept_;  // lanes: a triangle cut by spatial splits counts per leaf
            prims_ = Prims();  // as after a build: the blocks are the only copy
        } else {
            bvh8::prove_ids(tree_, blocks_, ids_, prim_bounds, clip);
            references_ = ids_.size();
        }
        adopt_layout(options.compressed);
        set_contexts();
    }
    Bvh8(const Bvh8&) = delete;  // ctx_ points into this object
    Bvh8& operator=(const Bvh8&) = delete;

    Aabb bounds() const override { return tree_.bounds; }

    /// The kernels' recording entry reports every step (bvh8/draw.h numbers them).
    static constexpr bool kRecordsSteps = true;
    bool for_each_node(const DrawnNodeVisitor& visit) const override {
        bvh8::for_each_node(ctx_, node_count_, kBlocks, visit);
        return true;
    }
    std::optional<DrawingLegend> drawing_legend() const override { return bvh8::draw_legend(); }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        if (node_count_ == 0) return miss_for(ray);
        if constexpr (RecordsSteps<C>) {
            // The counting traversal's own text with the recorder's calls compiled in (RecordFn).
            RayCounters counted;
            const Hit hit = kernels_->record[kLeafKind](ctx_, ray, &counted, bvh8::step_sink(counters, node_count_));
            counters.nodes += counted.nodes;
            counters.prims += counted.prims;
            return hit;
        } else if constexpr (std::is_same_v<C, RayCounters>)
            return kernels_->closest[kLeafKind][1](ctx_, ray, &counters);
        else
            return kernels_->closest[kLeafKind][0](ctx_, ray, nullptr);
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        if (node_count_ == 0) return false;
        if constexpr (std::is_same_v<C, RayCounters>)
            return kernels_->any[kLeafKind][1](ctx_, ray, &counters);
        else
            return kernels_->any[kLeafKind][0](ctx_, ray, nullptr);
    }

    /// The closest point of the triangles to p through the per-ISA point traversal, degenerate
    /// triangles included (their points are on the surface; rays never hit them); shapes: Error.
    NearestPoint closest_point(const Vec3& p) const override {
        if constexpr (kBlocks)
            return bvh8::closest_point(*kernels_, node_count_ == 0 ? nullptr : &ctx_, p);
        else
            return Accel::closest_point(p);  // shapes: refused with the reason
    }
    bool has_closest_point() const override { return kBlocks; }

    using Accel::all_hits;  // the batch forms stay visible next to the per-ray overrides
    using Accel::count_hits;

    /// Every crossing from one traversal that prunes nothing (triangle leaves): all the hits,
    /// sorted and merged by Accel::all_hits' rule (merge_crossings), which gives the crossings
    /// stepping from one to the next would, without a traversal per crossing. Shapes: stepping.
    void all_hits(const Ray& ray, std::vector<Hit>& out) const override {
        if constexpr (kBlocks)
            every_hit(ray, [&](std::span<Hit> hits) { merge_crossings(hits, &out); });
        else
            Accel::all_hits(ray, out);
    }
    uint32_t count_hits(const Ray& ray) const override {
        if constexpr (kBlocks) {
            uint32_t count = 0;
            every_hit(ray, [&](std::span<Hit> hits) { count = uint32_t(merge_crossings(hits, nullptr)); });
            return count;
        } else {
            return Accel::count_hits(ray);
        }
    }

    AccelStats stats() const override {
        AccelStats s = this->base_stats();
        bvh8::fill_stats(s, {.tree = &tree_,
                             .node_count = node_count_,
                             .node_bytes = qnodes_.empty() ? sizeof(bvh8::Node) : sizeof(bvh8::QNode),
                             .isa = kernels_->isa,
                             .primitives = primitives_,
                             .references = references_,
                             .ids = ids_.size(),
                             .primitive_bytes = kBlocks ? blocks_.size() * sizeof(bvh8::Tri4) : prims_.bytes(),
                             .blocks = kBlocks,
                             .block_count = blocks_.size(),
                             .lanes = kept_,
                             .degenerate = kBlocks ? bvh8::degenerate_lanes(blocks_) : 0,
                             .packet_rays = packet_rays_.load(std::memory_order_relaxed)});
        return s;
    }

    /// Compressed nodes are saved decoded (the format has one node layout: bvh8::decode_nodes);
    /// loading them with nodes=compressed quantizes those boxes again, which contain the exact ones.
    void save(std::ostream& out) const override {
        if (qnodes_.empty()) return bvh8::write_tree(out, tree_, blocks_, ids_);
        bvh8::Tree decoded = tree_;
        bvh8::decode_nodes(qnodes_, decoded.nodes);
        bvh8::write_tree(out, decoded, blocks_, ids_);
    }

    /// Accel::refit: new vertices into the blocks, every box and the plane bounds again
    /// (src/bvh8/refit.cpp); any move of the vertices is taken, degenerate triangles included
    /// (their lanes stay, never hit). Compressed nodes are decoded for the refit
    /// (their topology) and quantized again from the refitted boxes.
    void refit(const Scene& scene, unsigned threads) override {
        Prims fresh = refit_primitives(scene, primitives_, prims_, "bvh8");
        const bool compressed = !qnodes_.empty();
        if (compressed) bvh8::decode_nodes(qnodes_, tree_.nodes);
        try {
            if constexpr (kBlocks) {
                bvh8::refit_blocks(tree_, blocks_, fresh, threads);
            } else {
                bvh8::refit_tree(
                    tree_,
                    [&](uint32_t first, uint32_t size) {
                        Aabb b;
                        for (uint32_t k = first; k < first + size; ++k) b.grow(fresh.bounds(ids_[k]));
                        return b;
                    },
                    [](uint32_t, uint32_t size) { return size; }, threads);
                prims_ = std::move(fresh);
            }
        } catch (...) {
            if (compressed) tree_.nodes = {};  // the QNodes stand, unchanged
            throw;
        }
        adopt_layout(compressed);
        set_contexts();
    }
    bool refittable() const override { return true; }

    /// The tree's figures; its nodes are empty when they are compressed (qnodes()).
    const bvh8::Tree& tree() const { return tree_; }
    const bvh8::QNodes& qnodes() const { return qnodes_; }
    /// What the kernels read of the main tree, plane bounds included (refit's tests check them).
    const bvh8::TraceContext& trace_context() const { return ctx_; }
    const bvh8::KernelTable& kernels() const { return *kernels_; }
    const bvh8::Blocks& blocks() const { return blocks_; }

protected:
    /// Coherent batches: each 16 consecutive rays that share a direction octant (and have no zero
    /// direction component) go through the packet kernel; others, incoherent batches and every batch
    /// on a level without packets (KernelTable::packets false), ray by ray.
    void intersect_chunk(std::span<const Ray> rays, std::span<Hit> hits, bool coherent) const override {
        if (!coherent || !packets_ || !kernels_->packets || node_count_ == 0)
            return Accel::intersect_chunk(rays, hits, coherent);
        uint64_t in_packets = 0;
        for (size_t begin = 0; begin < rays.size(); begin += bvh8::kPacketSize) {
            const uint32_t count = uint32_t(std::min<size_t>(bvh8::kPacketSize, rays.size() - begin));
            if (count > 1 && bvh8::packet_eligible(&rays[begin], count)) {
                kernels_->packet_closest[kLeafKind](ctx_, &rays[begin], count, &hits[begin]);
                in_packets += count;
            } else {
                NoCounters none;
                for (size_t i = begin; i < begin + count; ++i) hits[i] = closest(rays[i], none);
            }
        }
        if (in_packets) packet_rays_.fetch_add(in_packets, std::memory_order_relaxed);  // once a chunk
    }

private:
    /// Stores the tree write_tree(emit) makes, whose leaves list primitives of `order` (the
    /// builder's leaf order, blocks_needed 4-triangle blocks at most): its leaves packed into
    /// blocks (degenerate triangles too: the kernels reject their hits) or kept as ids.
    template <class WriteTree>
    void adopt_build(const std::vector<uint32_t>& order, size_t blocks_needed, WriteTree&& write_tree) {
        references_ = order.size();
        if constexpr (kBlocks) {
            // Exactly the blocks the tree stores (an upper bound when packing drops repeated
            // triangles): never reallocated while written, never copied to fit.
            reserve_huge(blocks_, blocks_needed);
            bvh8::BlockPacking packing{references_ > primitives_};
            tree_ = write_tree([&](uint32_t first, uint32_t count) {
                return bvh8::pack_blocks(blocks_, prims_, order.data() + first, count, packing);
            });
            bvh8::validate_tree(tree_, blocks_.size());
            // Many repeated triangles (spatial splits) can leave the reservation above the need.
            if (blocks_.capacity() - blocks_.size() > blocks_.size() / 8) blocks_.shrink_to_fit();
            kept_ = packing.lanes;
            prims_ = Prims();  // the blocks are the structure's only copy of the triangles
        } else {
            ids_ = order;
            tree_ = write_tree([](uint32_t first, uint32_t count) { return bvh8::LeafPlacement{first, count}; });
            bvh8::validate_tree(tree_, ids_.size());
        }
    }

    /// Points the kernels' views at the trees and leaf storage this object holds.
    void set_contexts() {
        ctx_ = {.nodes = qnodes_.empty() ? tree_.nodes.data() : nullptr,
                .qnodes = qnodes_.empty() ? nullptr : qnodes_.data(),
                .blocks = blocks_.data(),
                .ids = ids_.data(),
                .prims = &prims_,
                .closest_leaf = &closest_leaf,
                .any_leaf = &any_leaf};
        if (qnodes_.empty())
            bvh8::set_plane_bounds(ctx_, tree_.nodes.data(), tree_.nodes.size());
        else
            bvh8::set_plane_bounds(ctx_, qnodes_.data(), qnodes_.size());
    }

    /// Counts the nodes and, for nodes=compressed, replaces them by their QNodes (the Nodes freed:
    /// the point is the memory).
    void adopt_layout(bool compressed) {
        node_count_ = tree_.nodes.size();
        if (!compressed || node_count_ == 0) return;
        qnodes_ = bvh8::compress_nodes(tree_.nodes);
        tree_.nodes = {};
    }

    /// Calls f(hits) with every hit of the ray (AllHitsFn's), in a buffer on the stack when they
    /// are few.
    template <class F>
    void every_hit(const Ray& ray, F&& f) const {
        if (node_count_ == 0) return;
        Hit few[64];
        const uint32_t n = kernels_->all_hits[kLeafKind](ctx_, ray, few, 64);
        if (n <= 64) return f(std::span<Hit>(few, n));
        std::vector<Hit> many(n);
        kernels_->all_hits[kLeafKind](ctx_, ray, many.data(), n);
        f(std::span<Hit>(many));
    }

    /// The kernels' callback leaves (kLeafCallback): the set's own tests, id by id.
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
    size_t kept_ = 0;        ///< block lanes filled (a triangle once per leaf listing it)
    size_t references_ = 0;  ///< entries of the binary tree's leaves
    bool packets_ = true;
    mutable std::atomic<uint64_t> packet_rays_{0};  ///< stats()' "packet rays"
    bvh8::Tree tree_;
    bvh8::QNodes qnodes_;         ///< nodes=compressed: the nodes rays see (tree_.nodes then empty)
    size_t node_count_ = 0;
    bvh8::Blocks blocks_;         ///< leaf storage of block leaves (kBlocks)
    std::vector<uint32_t> ids_;   ///< leaf storage of callback leaves
    const bvh8::KernelTable* kernels_;
    bvh8::TraceContext ctx_;
};

}  // namespace thicket
