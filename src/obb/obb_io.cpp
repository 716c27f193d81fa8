// OBB tree payload: the arrays' lengths, then the arrays as they are in memory. Reading checks
// every length against the scene and the bytes left before allocating (PayloadReader), then the
// structure (validate_obb); the Obb that adopts it proves its boxes (validate_obb_bounds).
#include <istream>
#include <ostream>
#include <string>

#include "thicket/core/error.h"
#include "thicket/obb/build.h"
#include "thicket/util/binary_io.h"

namespace thicket {

void write_obb(std::ostream& out, const ObbData& obb) {
    write_value(out, uint32_t(obb.nodes.size()));
    write_value(out, uint32_t(obb.prim_indices.size()));
    write_array(out, obb.nodes.data(), obb.nodes.size());
    write_array(out, obb.prim_indices.data(), obb.prim_indices.size());
}

ObbData read_obb(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "OBB");
    uint32_t nodes = 0, prims = 0;
    reader.value(nodes, "node count");
    reader.value(prims, "primitive count");
    if (prims != primitive_count)
        throw Error("OBB payload holds " + std::to_string(prims) + " primitives, the scene " +
                    std::to_string(primitive_count));
    ObbData obb;
    reader.array(obb.nodes, nodes, 2 * uint64_t(prims), "nodes");
    reader.array(obb.prim_indices, prims, prims, "primitive indices");
    reader.end();
    validate_obb(obb, primitive_count);
    return obb;
}

}  // namespace thicket
