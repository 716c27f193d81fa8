// BIH payload: the root box, the arrays' lengths, then the arrays as they are in memory (the BIH
// is relocatable). Reading checks the lengths against the scene and the bytes left before
// allocating (PayloadReader), then the structure.
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
    reader.array(bih.nodes, nodes, 4 * uint64_t(prims) + 1, "nodes");
    reader.array(bih.prim_indices, prims, prims, "primitive indices");
    reader.end();
    validate_bih(bih, primitive_count);
    return bih;
}

}  // namespace thicket
