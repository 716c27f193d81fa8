// BVH payload: the arrays' lengths, then the arrays as they are in memory (the BVH is
// relocatable). Reading checks every length against the scene and the bytes left before
// allocating (PayloadReader), then the structure.
#include <istream>
#include <ostream>

#include "thicket/bvh/build.h"
#include "thicket/core/error.h"
#include "thicket/util/binary_io.h"

namespace thicket {

void write_bvh(std::ostream& out, const BvhData& bvh) {
    write_value(out, uint32_t(bvh.nodes_used));
    write_value(out, uint32_t(bvh.prim_indices.size()));
    write_array(out, bvh.nodes.data(), bvh.nodes_used);
    write_array(out, bvh.child_order.data(), bvh.nodes_used);
    write_array(out, bvh.prim_indices.data(), bvh.prim_indices.size());
}

BvhData read_bvh(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "BVH");
    uint32_t nodes_used = 0, entries = 0;
    reader.value(nodes_used, "node count");
    // The index array's length: the primitive count, or more for a spatial-split tree (sbvh),
    // whose leaves list some primitives more than once.
    reader.value(entries, "primitive index count");
    if (entries < primitive_count || entries > uint64_t(kMaxReferencesPerPrimitive) * primitive_count)
        throw Error("BVH payload holds " + std::to_string(entries) + " primitive indices, the scene " +
                    std::to_string(primitive_count) + " primitives (at most " +
                    std::to_string(kMaxReferencesPerPrimitive) + " indices per primitive)");
    BvhData bvh;
    bvh.nodes_used = nodes_used;
    reader.array(bvh.nodes, nodes_used, 2 * uint64_t(entries), "nodes");
    reader.array(bvh.child_order, nodes_used, nodes_used, "child order");
    reader.array(bvh.prim_indices, entries, entries, "primitive indices");
    reader.end();
    validate_bvh(bvh, primitive_count);
    return bvh;
}

}  // namespace thicket
