// The default refit(): structures that keep no tree to refit, or whose cells depend on where the
// primitives are (grids, k-d trees, BSPs, octrees), say that they must be rebuilt.
#include "thicket/accel/accel.h"
#include "thicket/core/error.h"

namespace thicket {

void Accel::refit(const Scene&, unsigned) {
    const std::string name = spec().empty() ? std::string("this structure") : "'" + spec() + "'";
    throw Error(name + " cannot be refitted after vertices move (refit supports bvh, bvh8 and obb): rebuild it "
                       "with build_accel instead");
}

}  // namespace thicket
