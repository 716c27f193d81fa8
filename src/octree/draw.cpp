// The octree's drawing (octree/draw.h).
#include "thicket/octree/draw.h"

#include <vector>

#include "thicket/core/depth_first.h"

namespace thicket {

void draw_nodes(const OctreeData& o, const DrawnNodeVisitor& visit) {
    if (o.nodes.empty()) return;
    depth_first(NodeInBox{0, 0, o.root}, [&](const NodeInBox& it, std::vector<NodeInBox>& stack) {
        const OctreeNode& n = o.nodes[it.node];
        if (n.is_leaf()) {
            if (n.count != 0) visit(drawn_box(it.node, it.depth, it.box, true, n.count));
            return;
        }
        visit(drawn_box(it.node, it.depth, it.box, false, 0));
        for (int c = 7; c >= 0; --c) stack.push_back({n.index + uint32_t(c), it.depth + 1, octree_child_box(it.box, c)});
    });
}

DrawingLegend draw_legend(const OctreeData&) {
    return {"cells", "levels of the tree: its inner cells and non-empty leaf cells at this depth"};
}

}  // namespace thicket
