// BIH payload: the root box, then the arrays as they are in memory (the BIH is relocatable),
// each preceded by its length. Reading checks the lengths against the scene before allocating,
// then the structure.
#include <istream>
#include <ostream>
#include <string>

#include "thicket/bih/build.h"
#include "thicket/core/error.h"
#include "thicket/util/binary_io.h"

namespace thicket {

void write_bih(std::ostream& out, const BihData& bih) {
    write_value(out, bih.bounds);
    write_value(out, uint32_t(bih.nodes.size()));
    write_value(out, uint32_t(bih.prim_indices.size()));
    write_array(out, bih.nodes.data(), bih.nodes.size());
    write_array(out, bih.prim_indices.data(), bih.prim_indices.size());
}

BihData read_bih(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "BIH");
    BihData bih;
    uint32_t nodes = 0, prims = 0;
    reader.value(bih.bounds, "bounds");
    reader.value(nodes, "node count");
    reader.value(prims, "primitive count");
    if (prims != primitive_count)
        throw Error("BIH payload holds " + std::to_string(prims) + " primitives, the scene " +
                    std::to_string(primitive_count));
    if (nodes > 4 * size_t(prims) + 1)
        throw Error("BIH payload claims " + std::to_string(nodes) + " nodes for " + std::to_string(prims) +
                    " primitives");
    bih.nodes.resize(nodes);
    bih.prim_indices.resize(prims);
    reader.array(bih.nodes.data(), nodes, "nodes");
    reader.array(bih.prim_indices.data(), prims, "primitive indices");
    if (in.peek() != std::char_traits<char>::eof()) throw Error("BIH payload has trailing bytes");
    validate_bih(bih, primitive_count);
    return bih;
}

}  // namespace thicket
