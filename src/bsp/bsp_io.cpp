// BSP payload: the arrays as they are in memory (the tree is relocatable), each preceded by its
// length, then the root box, the scale and the splinter figures. Reading checks every length
// against the scene and the bytes left before allocating (PayloadReader), then the whole
// structure (validate_bsp); adopting it proves it is the tree the builder makes
// (prove_bsp_rebuilt, called by the Bsp's loading constructor).
#include <cmath>
#include <istream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "thicket/core/depth_first.h"
#include "thicket/bsp/build.h"
#include "thicket/core/error.h"
#include "thicket/util/binary_io.h"

namespace thicket {

namespace {

/// Most nodes and references a tree over `prims` primitives can have: every fragment is a
/// reference, fragments are at most kMaxBudget per primitive, and leaves never outnumber
/// fragments by more than the empty root.
constexpr uint64_t kMaxBudget = 1024;

}  // namespace

void write_bsp(std::ostream& out, const BspData& bsp) {
    write_value(out, uint64_t(bsp.nodes.size()));
    write_value(out, uint64_t(bsp.refs.size()));
    write_array(out, bsp.nodes.data(), bsp.nodes.size());
    write_array(out, bsp.refs.data(), bsp.refs.size());
    write_value(out, bsp.bounds);
    write_value(out, bsp.scale);
    const BspSplinters& f = bsp.splinters;
    for (uint64_t v : {f.fragments, f.splits, f.dropped, f.in_plane, f.split_triangles, f.pieces, f.measured_pieces,
                       f.slivers, f.depth_capped, f.budget_capped, f.unsplittable})
        write_value(out, v);
    write_value(out, f.smallest_area);
    write_value(out, f.smallest_ratio);
    write_value(out, uint8_t(f.polygons ? 1 : 0));
}

BspData read_bsp(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "BSP");
    uint64_t nodes = 0, refs = 0;
    reader.value(nodes, "node count");
    reader.value(refs, "reference count");
    const uint64_t max_refs = kMaxBudget * primitive_count;
    BspData bsp;
    reader.array(bsp.nodes, nodes, 2 * max_refs + 1, "nodes");
    reader.array(bsp.refs, refs, max_refs, "references");
    reader.value(bsp.bounds, "bounds");
    reader.value(bsp.scale, "scale");
    BspSplinters& f = bsp.splinters;
    for (uint64_t* v : {&f.fragments, &f.splits, &f.dropped, &f.in_plane, &f.split_triangles, &f.pieces,
                        &f.measured_pieces, &f.slivers, &f.depth_capped, &f.budget_capped, &f.unsplittable})
        reader.value(*v, "splinter figures");
    reader.value(f.smallest_area, "splinter figures");
    reader.value(f.smallest_ratio, "splinter figures");
    uint8_t polygons = 0;
    reader.value(polygons, "splinter figures");
    if (polygons > 1) throw Error("BSP payload: fragment kind " + std::to_string(polygons) + " is neither 0 nor 1");
    f.polygons = polygons == 1;
    reader.end();
    validate_bsp(bsp, primitive_count);
    return bsp;
}

void prove_bsp_rebuilt(const BspData& saved, const BspData& rebuilt) {
    std::ostringstream a, b;
    write_bsp(a, saved);
    write_bsp(b, rebuilt);
    const std::string x = a.str(), y = b.str();
    if (x == y) return;
    size_t at = 0;
    while (at < x.size() && at < y.size() && x[at] == y[at]) ++at;
    throw Error("invalid BSP: not the tree this scene and spec build (the payload differs from byte " +
                std::to_string(at) + " on); a BSP file is proved by rebuilding it (docs/fuzzing.md)");
}

void validate_bsp(const BspData& bsp, size_t primitive_count) {
    if (primitive_count == 0) {
        if (!bsp.nodes.empty() || !bsp.refs.empty()) throw Error("invalid BSP: nodes in a tree over no primitives");
        return;
    }
    if (bsp.nodes.empty()) throw Error("invalid BSP: no root node");
    if (bsp.nodes.size() >= (uint64_t(1) << 32) || bsp.refs.size() >= (uint64_t(1) << 31))
        throw Error("invalid BSP: too many nodes or references");
    if (!(bsp.scale >= 0.0f) || !std::isfinite(bsp.scale)) throw Error("invalid BSP: scale is not finite");
    for (uint32_t r : bsp.refs)
        if (r >= primitive_count)
            throw Error("invalid BSP: reference to primitive " + std::to_string(r) + " of " +
                        std::to_string(primitive_count));
    uint64_t covered = 0, reached = 0;
    depth_first(NodeAtDepth{0, 0}, [&](const NodeAtDepth& item, std::vector<NodeAtDepth>& stack) {
        const auto [i, depth] = item;
        ++reached;
        const BspNode& node = bsp.nodes[i];
        if (depth > kBspMaxDepth) throw Error("invalid BSP: deeper than " + std::to_string(kBspMaxDepth));
        if (node.is_leaf()) {
            if (uint64_t(node.index) + node.leaf_size() > bsp.refs.size())
                throw Error("invalid BSP: leaf " + std::to_string(i) + " references out of range");
            covered += node.leaf_size();
        } else {
            const Vec3& n = node.plane.normal;
            if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z) ||
                !std::isfinite(node.plane.offset) || std::fabs(dot(n, n) - 1.0f) > 1e-3f)
                throw Error("invalid BSP: node " + std::to_string(i) + " has no unit plane");
            // Children always come after their parent: this rules out cycles.
            if (node.index <= i || uint64_t(node.index) + 1 >= bsp.nodes.size())
                throw Error("invalid BSP: node " + std::to_string(i) + " has children out of range");
            stack.push_back({node.index, depth + 1});
            stack.push_back({node.index + 1, depth + 1});
        }
    });
    if (reached != bsp.nodes.size())
        throw Error("invalid BSP: " + std::to_string(bsp.nodes.size() - reached) + " nodes are unreachable");
    if (covered != bsp.refs.size())
        throw Error("invalid BSP: leaves cover " + std::to_string(covered) + " of " + std::to_string(bsp.refs.size()) +
                    " references");
}

}  // namespace thicket
