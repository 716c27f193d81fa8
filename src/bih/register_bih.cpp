#include "accel/dispatch.h"
#include "thicket/bih/bih.h"

namespace thicket {

namespace {

constexpr Choice<BihEmptySide> kEmptySides[] = {{"cut", BihEmptySide::Cut}, {"refine", BihEmptySide::Refine}};

BihBuildOptions build_options(const AccelSpec& spec) {
    BihBuildOptions o;
    o.max_leaf = int(spec.get_int("max-leaf"));
    o.empty_side = spec.choice("empty", kEmptySides);
    return o;
}

}  // namespace

void register_bih(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "bih";
    info.partitioning = Partitioning::Object;
    info.summary = "bounding interval hierarchy (Waechter & Keller 2006): 12-byte nodes with two clip planes, "
                   "global-heuristic build";
    info.options = {
        {"max-leaf", "a range of at most this many primitives becomes a leaf", "4", {}, 1, 255},
        choice_option("empty",
                      "when every object falls on one side of the candidate plane: refine (halve the candidate box, "
                      "make no node) or cut (also make a node with an empty child when that cuts off a quarter of "
                      "the node's extent)",
                      BihEmptySide::Cut, kEmptySides),
    };
    info.variants = {"bih", "bih:empty=refine", "bih:max-leaf=1", "bih:isect=watertight"};
    set_build_and_load<Bih>(info, build_options, read_bih);
    registry.push_back(std::move(info));
}

}  // namespace thicket
