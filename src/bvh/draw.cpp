// The BVH's drawing (bvh/draw.h).
#include "thicket/bvh/draw.h"

#include <vector>

#include "thicket/core/depth_first.h"

namespace thicket {

void draw_nodes(const BvhData& bvh, const DrawnNodeVisitor& visit) {
    if (bvh.nodes_used == 0) return;
    depth_first(NodeAtDepth{0, 0}, [&](const NodeAtDepth& it, std::vector<NodeAtDepth>& stack) {
        const BvhNode& n = bvh.nodes[it.node];
        visit(drawn_box(it.node, it.depth, n.bounds(), n.is_leaf(), n.is_leaf() ? n.count : 0));
        if (n.is_leaf()) return;
        stack.push_back({n.leftFirst + 1, it.depth + 1});
        stack.push_back({n.leftFirst, it.depth + 1});
    });
}

DrawingLegend draw_legend(const BvhData&) {
    return {"boxes", "levels of the tree: the boxes of the nodes at this depth"};
}

}  // namespace thicket
