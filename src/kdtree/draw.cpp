// The kD-tree's drawing (kdtree/draw.h).
#include "thicket/kdtree/draw.h"

#include <utility>
#include <vector>

#include "thicket/core/depth_first.h"

namespace thicket {

void draw_nodes(const KdTreeData& kd, const DrawnNodeVisitor& visit) {
    if (kd.nodes.empty()) return;
    depth_first(NodeInBox{0, 0, kd.bounds}, [&](const NodeInBox& it, std::vector<NodeInBox>& stack) {
        const KdNode& n = kd.nodes[it.node];
        if (n.is_leaf()) {
            // Empty leaves (the SAH's cut-off empty space) are not drawn.
            if (n.count() != 0) visit(drawn_box(it.node, it.depth, it.box, true, n.count()));
            return;
        }
        const int a = n.axis(), u = (a + 1) % 3, v = (a + 2) % 3;
        const float s = n.split();
        DrawnNode plane = drawn_box(it.node, it.depth, it.box, false, 0);
        plane.shape = DrawnNode::Shape::Plane;
        for (const auto& [hu, hv] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
            Vec3 p;
            p[a] = s;
            p[u] = hu ? it.box.max[u] : it.box.min[u];
            p[v] = hv ? it.box.max[v] : it.box.min[v];
            plane.points.push_back(p);
        }
        visit(plane);
        Aabb below = it.box, above = it.box;
        below.max[a] = s;
        above.min[a] = s;
        stack.push_back({n.above(), it.depth + 1, above});
        stack.push_back({it.node + 1, it.depth + 1, below});
    });
}

DrawingLegend draw_legend(const KdTreeData&) {
    return {"planes and leaf cells", "levels of the tree: the planes of the nodes at this depth, "
                                     "and the non-empty leaves that end here"};
}

}  // namespace thicket
