// The BIH's drawing (bih/draw.h).
#include "thicket/bih/draw.h"

#include <algorithm>
#include <vector>

#include "thicket/core/depth_first.h"

namespace thicket {

void draw_nodes(const BihData& b, const DrawnNodeVisitor& visit) {
    if (b.nodes.empty()) return;
    depth_first(NodeInBox{0, 0, b.bounds}, [&](const NodeInBox& it, std::vector<NodeInBox>& stack) {
        if (it.box.empty()) return;
        const BihNode& n = b.nodes[it.node];
        visit(drawn_box(it.node, it.depth, it.box, n.is_leaf(), n.is_leaf() ? n.count() : 0));
        if (n.is_leaf()) return;
        const int a = n.axis();
        Aabb left = it.box, right = it.box;
        left.max[a] = std::min(left.max[a], n.left_max());
        right.min[a] = std::max(right.min[a], n.right_min());
        stack.push_back({n.index() + 1, it.depth + 1, right});
        stack.push_back({n.index(), it.depth + 1, left});
    });
}

DrawingLegend draw_legend(const BihData&) {
    return {"boxes", "levels of the tree: each node's box, the root box cut by the intervals above it"};
}

}  // namespace thicket
