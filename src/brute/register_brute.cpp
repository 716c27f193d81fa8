#include "accel/dispatch.h"
#include "thicket/brute/brute_force.h"

namespace thicket {

void register_brute(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "brute";
    info.summary = "brute force: tests every primitive; the reference every structure is checked against";
    info.partitioning = Partitioning::None;
    info.variants = {"brute", "brute:isect=watertight"};
    info.build = [](const Scene& scene, const AccelSpec& spec) { return make_structure<BruteForce>(scene, spec); };
    registry.push_back(std::move(info));
}

}  // namespace thicket
