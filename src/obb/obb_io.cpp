// OBB tree payload: the arrays as they are in memory, each preceded by its length. Reading
// checks every length against the scene before allocating, then the structure.
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
    if (nodes > 2 * size_t(prims))
        throw Error("OBB payload claims " + std::to_string(nodes) + " nodes for " + std::to_string(prims) +
                    " primitives");
    ObbData obb;
    obb.nodes.resize(nodes);
    obb.prim_indices.resize(prims);
    reader.array(obb.nodes.data(), nodes, "nodes");
    reader.array(obb.prim_indices.data(), prims, "primitive indices");
    if (in.peek() != std::char_traits<char>::eof()) throw Error("OBB payload has trailing bytes");
    validate_obb(obb, primitive_count);
    return obb;
}

}  // namespace thicket
