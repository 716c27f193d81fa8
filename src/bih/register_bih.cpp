#include "accel/dispatch.h"
#include "thicket/bih/bih.h"

namespace thicket {

namespace {

constexpr Choice<BihEmptySide> kEmptySides[] = {{"cut", BihEmptySide::Cut}, {"refine", BihEmptySide::Refine}};

}  // namespace

void register_bih(std::vector<AccelInfo>& registry) {
    const OptionFields<BihBuildOptions> fields = {
        int_field("max-leaf", "a range of at most this many primitives becomes a leaf", &BihBuildOptions::max_leaf, 1,
                  255),
        choice_field("empty",
                     "when every object falls on one side of the candidate plane: refine (halve the candidate box, "
                     "make no node) or cut (also make a node with an empty child when that cuts off a quarter of "
                     "the node's extent)",
                     &BihBuildOptions::empty_side, kEmptySides),
    };
    AccelInfo info = accel_info({.name = "bih",
                                 .partitioning = Partitioning::Object,
                                 .summary = "bounding interval hierarchy (Waechter & Keller 2006): 12-byte nodes with "
                                            "two clip planes, global-heuristic build",
                                 .variants = {"bih", "bih:empty=refine", "bih:max-leaf=1", "bih:isect=watertight"}},
                                fields);
    set_build_and_load<Bih>(info, fields, read_bih);
    registry.push_back(std::move(info));
}

}  // namespace thicket
