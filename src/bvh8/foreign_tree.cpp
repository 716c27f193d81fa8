// The one installed foreign tree builder (bvh8:tree=embree-*).
#include "thicket/bvh8/foreign_tree.h"

#include <atomic>

#include "thicket/core/error.h"

namespace thicket::bvh8 {

namespace {
std::atomic<ForeignTreeBuilder> installed{nullptr};
}  // namespace

void set_foreign_tree_builder(ForeignTreeBuilder builder) { installed.store(builder); }

WideTree build_foreign_tree(const ForeignTreeRequest& request) {
    const ForeignTreeBuilder builder = installed.load();
    if (!builder)
        throw Error("bvh8: tree=" + std::string(request.source == TreeSource::EmbreeHigh ? "embree-high" : "embree-medium") +
                    " needs Embree's builder, which only `thicket bench` links (built with Embree); use tree=thicket");
    return builder(request);
}

}  // namespace thicket::bvh8
