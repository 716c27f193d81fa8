// The oriented-box hierarchy's drawing (obb/draw.h).
#include "thicket/obb/draw.h"

#include <vector>

#include "thicket/core/depth_first.h"

namespace thicket {

void draw_nodes(const ObbData& o, const DrawnNodeVisitor& visit) {
    if (o.nodes.empty()) return;
    depth_first(NodeAtDepth{0, 0}, [&](const NodeAtDepth& it, std::vector<NodeAtDepth>& stack) {
        const ObbNode& n = o.nodes[it.node];
        DrawnNode d = drawn_box(it.node, it.depth, Aabb{}, n.is_leaf(), n.count);
        d.shape = DrawnNode::Shape::Oriented;
        d.points = {n.center, n.axis[0] * n.half.x, n.axis[1] * n.half.y, n.axis[2] * n.half.z};
        visit(d);
        if (n.is_leaf()) return;
        stack.push_back({n.leftFirst + 1, it.depth + 1});
        stack.push_back({n.leftFirst, it.depth + 1});
    });
}

DrawingLegend draw_legend(const ObbData&) {
    return {"oriented boxes", "levels of the tree: the oriented boxes of the nodes at this depth"};
}

}  // namespace thicket
