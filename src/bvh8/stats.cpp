// bvh8's statistics from plain figures: AccelStats' shared fields, then its own ("isa",
// "8-wide nodes", "Embree SAH", blocks, "degenerate lanes", "references").
#include "thicket/bvh8/stats.h"

#include <cstdint>
#include <string>

#include "thicket/bvh/build.h"

namespace thicket::bvh8 {

void fill_stats(AccelStats& s, const StatsFigures& f) {
    const Tree& tree = *f.tree;
    s.primitives = f.primitives;
    s.nodes = f.node_count + tree.leaves;  // AccelStats counts leaves as nodes
    s.leaves = tree.leaves;
    s.max_depth = tree.max_depth;
    s.bytes = f.node_count * f.node_bytes + f.ids * sizeof(uint32_t);
    s.primitive_bytes = f.primitive_bytes;
    s.sah_cost = tree.sah_cost;
    s.extra.emplace_back("isa", f.isa);
    s.extra.emplace_back("8-wide nodes", std::to_string(f.node_count) +
                                              (f.node_bytes == sizeof(Node) ? "" : " (compressed, " +
                                                  std::to_string(f.node_bytes) + " bytes each)"));
    s.extra.emplace_back("Embree SAH", std::to_string(tree.embree_sah_cost));
    if (f.blocks) {
        const size_t lanes = f.block_count * 4;
        s.extra.emplace_back("4-triangle blocks", std::to_string(f.block_count) + " (" +
                                                      std::to_string(lanes ? 100 * f.lanes / lanes : 0) +
                                                      "% of lanes used)");
        s.extra.emplace_back("degenerate lanes", std::to_string(f.degenerate));
    }
    // Counted, not structural: the proof that coherent batches took the packet path (tests, CI).
    s.extra.emplace_back("packet rays", std::to_string(f.packet_rays));
    // More references than primitives: spatial splits (builder=sbvh) list some in several leaves.
    s.extra.emplace_back("references", reference_figure(f.references, f.primitives));
}

}  // namespace thicket::bvh8
