#pragma once
/// The 8-wide BVH's memory layout and the plain-data interface between the structure (compiled
/// for the baseline ISA) and its traversal kernels (one translation unit per ISA, src/bvh8/).
/// Everything here is data or a declaration: no function body, so that no inline code is shared
/// between translation units compiled for different ISAs (see docs/bvh8.md, "The dispatch trap").
#include <cstddef>
#include <cstdint>

#include "thicket/core/degenerate.h"
#include "thicket/core/ray.h"

namespace thicket::bvh8 {

inline constexpr int kWidth = 8;

/// One 256-byte node: the boxes of its 8 children as structure-of-arrays floats, so that one
/// vector load fetches one plane of all 8 boxes. box[axis][0][lane] is the lower bound on that
/// axis, box[axis][1][lane] the upper. A lane is a child only if its bit in `valid` is set; an
/// empty lane's box is inverted (+inf, -inf), but the mask, not the box, is what excludes it
/// (a ray with a NaN or infinite component can still pass an inverted box's slab test).
struct alignas(64) Node {
    float box[3][2][kWidth];
    uint32_t child[kWidth];       ///< node index if leaf_size is 0, else the leaf's first block/id
    uint8_t leaf_size[kWidth];    ///< 0: child is a node; else 4-triangle blocks or primitive ids
    uint32_t valid;               ///< bit i set: lane i holds a child
};
static_assert(sizeof(Node) == 256, "four cache lines per node, as Embree's BVH8");

/// `bvh8:nodes=compressed`'s 96-byte node (two cache lines; Ylitie, Karras & Laine 2017, Embree's
/// QBVH8): each child plane an 8-bit step count from the node's origin, decoded as
/// plane = origin[a] + q[a][side][lane] * 2^exponent[a]. q * 2^e is exact (8 bits times a power of
/// two), so the sum rounds once whether fused or not and every ISA decodes the same floats.
/// Lower planes are rounded down and upper planes up (compress.h), so a decoded box contains the
/// child's exact box: the kernels test decoded boxes as they test a Node's, hits are unchanged.
struct alignas(32) QNode {
    float origin[3];
    int8_t exponent[3];           ///< -126..127: 2^e is a normal float
    uint8_t valid;                ///< bit i set: lane i holds a child
    uint8_t q[3][2][kWidth];      ///< [axis][0: lower, 1: upper][lane]
    uint32_t child[kWidth];       ///< Node::child | Node::leaf_size << kQIndexBits
};
static_assert(sizeof(QNode) == 96, "two cache lines wherever a 32-byte aligned node starts");
/// A QNode's child word: the index in the low bits, the leaf size (0: a node) in the high 8.
inline constexpr uint32_t kQIndexBits = 24;

/// Four triangles as structure-of-arrays: v[k][axis][lane] is vertex k of triangle `lane`.
/// The vertices are stored, not v0 and two edges, because the kept hit must be bitwise the
/// scalar Moller-Trumbore's, which computes e1 = v1 - v0 itself, and the plausibility filter
/// needs each triangle's exact box. Unused lanes have id kNoPrim and all-zero vertices (a zero
/// determinant: never hit).
struct alignas(16) Tri4 {
    float v[3][3][4];
    uint32_t id[4];
};
static_assert(sizeof(Tri4) == 160, "ten 16-byte vectors");

/// How a leaf's primitives are tested.
enum LeafKind : int {
    kLeafMoller = 0,      ///< Tri4 blocks, Moller-Trumbore on 4 lanes
    kLeafWatertight = 1,  ///< Tri4 blocks, the watertight test lane by lane
    kLeafCallback = 2,    ///< primitive ids, tested one by one through the PrimitiveSet
    kLeafKinds = 3
};

/// Leaf tests of a PrimitiveSet, provided by the structure's baseline code (kLeafCallback).
using ClosestLeafFn = bool (*)(const void* prims, const uint32_t* ids, uint32_t count, const Ray& ray, Hit& hit);
using AnyLeafFn = bool (*)(const void* prims, const uint32_t* ids, uint32_t count, const Ray& ray);

/// What a traversal kernel reads: the node array (root at 0, never empty when a kernel runs),
/// the leaf storage and, for callback leaves, the primitive set.
struct TraceContext {
    const Node* nodes = nullptr;
    /// Set instead of nodes (null) for nodes=compressed: the same tree, quantized boxes.
    const QNode* qnodes = nullptr;
    const Tri4* blocks = nullptr;
    const uint32_t* ids = nullptr;
    const void* prims = nullptr;
    ClosestLeafFn closest_leaf = nullptr;
    AnyLeafFn any_leaf = nullptr;
    /// Every valid lane's box of every node lies within [plane_lo, plane_hi] on each axis: what
    /// bounds the error of the FMA slab test (docs/bvh8.md, "The slab test at one FMA per
    /// plane"). Set by set_plane_bounds; an empty or non-finite range sends every ray to the
    /// exact slab test.
    float plane_lo[3] = {0.0f, 0.0f, 0.0f};
    float plane_hi[3] = {-1.0f, -1.0f, -1.0f};
};

/// Sets ctx.plane_lo/hi to the range of every valid lane's box of nodes[0..count) (NaN planes
/// ignored): computed over all nodes, not the root alone, so that a loaded file whose children
/// stick out of their parents cannot make the FMA test cull.
void set_plane_bounds(TraceContext& ctx, const Node* nodes, size_t count);

/// Closest hit / any hit; counters is null for the non-counting entry ([1] of each table row).
using ClosestFn = Hit (*)(const TraceContext& ctx, const Ray& ray, RayCounters* counters);
using AnyFn = bool (*)(const TraceContext& ctx, const Ray& ray, RayCounters* counters);
/// The 8-wide slab test of `count` nodes with one ray (set up once, as in a traversal): returns
/// the mask of lanes of the last node entered within [ray.tmin, tmax] and writes their entry
/// distances to dist[0..8); the OR of all masks is in *any_mask (the micro-benchmarks' node kernel).
using NodeTestFn = uint32_t (*)(const Node* nodes, uint32_t count, const Ray& ray, float tmax, float* dist,
                                uint32_t* any_mask);
/// The traversal's slab test of `count` nodes with one ray, as NodeTestFn: the conservative FMA
/// test against ctx's plane bounds where the ray allows it (*fma set true), else the exact one.
/// It enters every lane the exact test enters, at an entry distance no greater
/// (tests/unit/bvh8_fma_slab_test.cpp).
using FastNodeTestFn = uint32_t (*)(const TraceContext& ctx, const Node* nodes, uint32_t count, const Ray& ray,
                                    float tmax, float* dist, uint32_t* any_mask, bool* fma);
/// FastNodeTestFn on compressed nodes, as the traversal runs it: the planes decoded, then the
/// FMA test (or the exact one) on them. It enters every lane the exact test of the decoded node
/// enters, at an entry distance no greater (tests/unit/bvh8_fma_slab_test.cpp).
using CompressedNodeTestFn = uint32_t (*)(const TraceContext& ctx, const QNode* nodes, uint32_t count,
                                          const Ray& ray, float tmax, float* dist, uint32_t* any_mask, bool* fma);
/// Moller-Trumbore on one block: mask of lanes hit within [ray.tmin, tmax], their t.
using BlockTestFn = uint32_t (*)(const Tri4& block, const Ray& ray, float tmax, float* t);

/// Closest hits of a packet: rays[0..count), 1 <= count <= kPacketSize, all in one direction octant
/// and with finite 1/dir on every axis, into hits[0..count): what ClosestFn answers for each ray
/// (the primitive may differ only between primitives hit at the very same t).
using PacketClosestFn = void (*)(const TraceContext& ctx, const Ray* rays, uint32_t count, Hit* hits);
/// What a counting packet traversal did (issue 45: the packets' pruning is checked against single
/// rays). Nodes the packet visited together: one box test of its 8 children against the whole
/// packet, or one leaf entered by some of its rays. The single rays' own work: nodes of the
/// subtrees rays finished alone, and every primitive test of every ray (in packet leaves too).
struct PacketCounters {
    uint64_t packet_nodes = 0;
    uint64_t ray_nodes = 0;
    uint64_t prims = 0;
};
/// PacketClosestFn counting into `counters`: the same hits, from the same source as every packet
/// kernel with the octant read at run time (as every tree but the default one traces packets; the
/// default tree's octant copies hand lone rays to the exact slab test, this one to the FMA test,
/// which may enter a few more boxes).
using CountingPacketClosestFn = void (*)(const TraceContext& ctx, const Ray* rays, uint32_t count, Hit* hits,
                                         PacketCounters* counters);
inline constexpr uint32_t kPacketSize = 16;

/// A point query's leaf test, in the structure's baseline code (the point-triangle test brute
/// force uses, so that distances are bitwise brute force's): tests leaf storage [first, first +
/// size) against the query point, keeps anything closer in `query`, and returns the squared
/// distance beyond which boxes are pruned from now on.
using PointLeafFn = float (*)(void* query, uint32_t first, uint32_t size);
/// Closest-point traversal of ctx's tree (nodes, and blocks to prefetch) from the root: children
/// whose box lies within the bound are visited nearest box first, the others wait on a stack and
/// are dropped when popped beyond the bound `leaf` returned last. p is the query point (3 floats),
/// bound2 the starting squared bound (+inf: none).
using PointQueryFn = void (*)(const TraceContext& ctx, const float* p, float bound2, PointLeafFn leaf, void* query);

/// Every hit of a ray within [ray.tmin, ray.tmax] (triangle leaves): the first `capacity` in
/// out[], in no particular order, a primitive once per leaf that references it; returns how many
/// there are (more than capacity: call again with room for all).
using AllHitsFn = uint32_t (*)(const TraceContext& ctx, const Ray& ray, Hit* out, uint32_t capacity);

/// Where a recording traversal (RecordFn) reports its steps: plain function pointers into
/// baseline code (src/bvh8/record.cpp), so that no recorder code is compiled for a kernel's ISA.
/// Ids are for_each_node's (bvh8/draw.h): a node's index, or leaf_base plus a leaf's first
/// block or id.
struct StepSink {
    void* recorder = nullptr;
    uint32_t leaf_base = 0;  ///< the node count
    void (*node)(void* recorder, uint32_t id, float t_enter) = nullptr;  ///< entered, or culled at +inf
    void (*skip)(void* recorder, uint32_t id, float t_enter) = nullptr;  ///< deferred, then dropped
    void (*prim)(void* recorder, uint32_t id, float closest) = nullptr;  ///< tested; closest after it
};

/// Closest hit as ClosestFn's counting entry answers it (the same nodes in the same order, the
/// same hit), every step told to `sink`: the root entered at ray.tmin (its box is never tested,
/// its children's are); each visited node's children tested, the culled ones in lane order and
/// then the entered ones in the order they will be visited (nearest first, ties in lane order);
/// each deferred child dropped when popped beyond the hit; each leaf's primitives in storage
/// order with the closest distance after each. Counts into `counters` as ClosestFn does.
using RecordFn = Hit (*)(const TraceContext& ctx, const Ray& ray, RayCounters* counters, const StepSink& sink);

/// One ISA's kernels.
struct KernelTable {
    const char* isa;
    /// Whether packet_closest traces packets: false where the level has no packet kernel (AVX2, the
    /// scalar reference), which then answers each ray alone, and Bvh8 sends coherent batches ray by
    /// ray instead, so that "packet rays" counts only rays a packet kernel traced.
    bool packets;
    ClosestFn closest[kLeafKinds][2];  ///< [kind][0: no counters, 1: counting]
    AnyFn any[kLeafKinds][2];
    NodeTestFn node_test;
    FastNodeTestFn node_test_fast;
    CompressedNodeTestFn node_test_compressed;
    BlockTestFn block_test;
    PacketClosestFn packet_closest[kLeafKinds];
    CountingPacketClosestFn packet_closest_counting[kLeafKinds];
    PointQueryFn closest_point;
    AllHitsFn all_hits[kLeafKinds];  ///< null for leaves of shapes (Accel::all_hits answers)
    RecordFn record[kLeafKinds];     ///< one instantiation per leaf kind, the octant read at run time
};

}  // namespace thicket::bvh8
