// bvh8's drawing and recording side in baseline code (bvh8/draw.h).
#include "thicket/bvh8/draw.h"

#include <vector>

#include "thicket/bvh8/compress.h"
#include "thicket/core/depth_first.h"

namespace thicket::bvh8 {

namespace {

/// Lane `lane`'s box of n.
Aabb lane_box(const Node& n, int lane) {
    return Aabb{{n.box[0][0][lane], n.box[1][0][lane], n.box[2][0][lane]},
                {n.box[0][1][lane], n.box[1][1][lane], n.box[2][1][lane]}};
}

}  // namespace

void for_each_node(const TraceContext& ctx, size_t node_count, bool blocks, const DrawnNodeVisitor& visit) {
    if (node_count == 0) return;
    // Node `i` as the kernels read it: decoded planes for nodes=compressed.
    const auto node = [&](uint32_t i) { return ctx.qnodes ? decode_node(ctx.qnodes[i]) : ctx.nodes[i]; };
    struct Lane {
        uint32_t child, leaf_size, depth;
        Aabb box;
    };
    const Node root = node(0);
    Aabb root_box;
    for (int lane = 0; lane < kWidth; ++lane)
        if (root.valid >> lane & 1u) root_box.grow(lane_box(root, lane));
    depth_first(Lane{0, 0, 0, root_box}, [&](const Lane& it, std::vector<Lane>& stack) {
        if (it.leaf_size != 0) {
            uint32_t prims = it.leaf_size;
            if (blocks) {
                prims = 0;
                for (uint32_t k = it.child; k < it.child + it.leaf_size; ++k)
                    for (uint32_t id : ctx.blocks[k].id) prims += id != kNoPrim;
            }
            visit(drawn_box(uint32_t(node_count) + it.child, it.depth, it.box, true, prims));
            return;
        }
        visit(drawn_box(it.child, it.depth, it.box, false, 0));
        // Pre-order, lanes in order: a node's parent is the last node listed one level up.
        const Node n = node(it.child);
        for (int lane = kWidth - 1; lane >= 0; --lane)
            if (n.valid >> lane & 1u) stack.push_back({n.child[lane], n.leaf_size[lane], it.depth + 1, lane_box(n, lane)});
    });
}

DrawingLegend draw_legend() { return {"boxes", "levels of the tree: the boxes of the nodes at this depth"}; }

StepSink step_sink(TraversalRecorder& recorder, size_t node_count) {
    StepSink sink;
    sink.recorder = &recorder;
    sink.leaf_base = uint32_t(node_count);
    sink.node = [](void* r, uint32_t id, float t) { static_cast<TraversalRecorder*>(r)->record_node(id, t); };
    sink.skip = [](void* r, uint32_t id, float t) { static_cast<TraversalRecorder*>(r)->record_skip(id, t); };
    sink.prim = [](void* r, uint32_t id, float t) { static_cast<TraversalRecorder*>(r)->record_prim(id, t); };
    return sink;
}

}  // namespace thicket::bvh8
