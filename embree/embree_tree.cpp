#include "embree_tree.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "thicket/bvh8/foreign_tree.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

/// What the callbacks write into Embree's thread-local memory: an inner node or a leaf, told
/// apart by the first field.
struct Item {
    bool leaf;
    uint32_t count;  ///< children, or primitives (their ids follow a LeafItem)
};
struct InnerItem : Item {
    void* child[8];
    RTCBounds box[8];
};
struct LeafItem : Item {
    uint32_t* ids() { return reinterpret_cast<uint32_t*>(this + 1); }
};

struct BuildLog {
    std::mutex mutex;
    std::string first_error;
};

void on_error(void* user, RTCError code, const char* message) {
    auto* log = static_cast<BuildLog*>(user);
    std::lock_guard<std::mutex> lock(log->mutex);
    if (log->first_error.empty())
        log->first_error = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "(no message)");
}

void* create_node(RTCThreadLocalAllocator alloc, unsigned count, void*) {
    auto* node = static_cast<InnerItem*>(rtcThreadLocalAlloc(alloc, sizeof(InnerItem), 16));
    node->leaf = false;
    node->count = count;
    return node;
}

void set_children(void* node, void** children, unsigned count, void*) {
    for (unsigned i = 0; i < count; ++i) static_cast<InnerItem*>(node)->child[i] = children[i];
}

void set_bounds(void* node, const RTCBounds** bounds, unsigned count, void*) {
    for (unsigned i = 0; i < count; ++i) static_cast<InnerItem*>(node)->box[i] = *bounds[i];
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
    auto* leaf = static_cast<LeafItem*>(rtcThreadLocalAlloc(alloc, sizeof(LeafItem) + count * sizeof(uint32_t), 16));
    leaf->leaf = true;
    leaf->count = uint32_t(count);
    for (size_t i = 0; i < count; ++i) leaf->ids()[i] = prims[i].primID;
    return leaf;
}

RTCBounds to_rtc(const Aabb& b) {
    RTCBounds r{};
    r.lower_x = b.min.x, r.lower_y = b.min.y, r.lower_z = b.min.z;
    r.upper_x = b.max.x, r.upper_y = b.max.y, r.upper_z = b.max.z;
    return r;
}
Aabb from_rtc(const RTCBounds& r) { return {{r.lower_x, r.lower_y, r.lower_z}, {r.upper_x, r.upper_y, r.upper_z}}; }

/// Embree's spatial split of one (possibly already cut) primitive at `position` on `dim`: its
/// part on each side, clipped exactly by the set.
void split_primitive(const RTCBuildPrimitive* prim, unsigned dim, float position, RTCBounds* left, RTCBounds* right,
                     void* user) {
    const auto* request = static_cast<const bvh8::ForeignTreeRequest*>(user);
    const Aabb box{{prim->lower_x, prim->lower_y, prim->lower_z}, {prim->upper_x, prim->upper_y, prim->upper_z}};
    Aabb lo = box, hi = box;
    lo.max[int(dim)] = position;
    hi.min[int(dim)] = position;
    lo = request->clip(prim->primID, lo);
    hi = request->clip(prim->primID, hi);
    *left = to_rtc(lo);
    *right = to_rtc(hi);
}

bool usable(const Aabb& b) {
    for (int a = 0; a < 3; ++a)
        if (!(std::isfinite(b.min[a]) && std::isfinite(b.max[a]) && b.min[a] <= b.max[a])) return false;
    return true;
}

/// Embree's tree copied out of its memory, depth first from the root (items[0]).
bvh8::WideTree copy_tree(const Item* root, const Aabb& root_box) {
    bvh8::WideTree wide;
    struct Todo {
        const Item* item;
        uint32_t index;
    };
    wide.items.push_back({root_box, 0, 0, root->leaf});
    std::vector<Todo> todo{{root, 0}};
    while (!todo.empty()) {
        const Todo t = todo.back();
        todo.pop_back();
        if (t.item->leaf) {
            auto* leaf = static_cast<LeafItem*>(const_cast<Item*>(t.item));
            wide.items[t.index].first = uint32_t(wide.prims.size());
            wide.items[t.index].count = leaf->count;
            wide.prims.insert(wide.prims.end(), leaf->ids(), leaf->ids() + leaf->count);
            continue;
        }
        const auto* node = static_cast<const InnerItem*>(t.item);
        wide.items[t.index].first = uint32_t(wide.children.size());
        wide.items[t.index].count = node->count;
        for (uint32_t i = 0; i < node->count; ++i) {
            const auto* child = static_cast<const Item*>(node->child[i]);
            const uint32_t index = uint32_t(wide.items.size());
            wide.items.push_back({from_rtc(node->box[i]), 0, 0, child->leaf});
            wide.children.push_back(index);
            todo.push_back({child, index});
        }
    }
    return wide;
}

bvh8::WideTree build_with_embree(const bvh8::ForeignTreeRequest& request) {
    const bool high = request.source == bvh8::TreeSource::EmbreeHigh;
    std::vector<RTCBuildPrimitive> prims;
    Aabb root_box;
    for (size_t i = 0; i < request.prim_bounds.size(); ++i) {
        const Aabb& b = request.prim_bounds[i];
        if (!usable(b)) continue;  // NaN or infinite vertices: nothing to hit
        root_box.grow(b);
        RTCBuildPrimitive p;
        p.lower_x = b.min.x, p.lower_y = b.min.y, p.lower_z = b.min.z, p.geomID = 0;
        p.upper_x = b.max.x, p.upper_y = b.max.y, p.upper_z = b.max.z, p.primID = uint32_t(i);
        prims.push_back(p);
    }
    if (prims.empty()) return {};
    const size_t count = prims.size();
    // Embree's scene builders give spatial splits 20% more references (common/state.cpp).
    if (high) prims.resize(count + (count + 4) / 5);

    const std::string config = request.threads ? "threads=" + std::to_string(request.threads) : "";
    RTCDevice device = rtcNewDevice(config.c_str());
    if (!device) throw Error("Embree: cannot create a device for tree=embree-*");
    BuildLog log;
    rtcSetDeviceErrorFunction(device, on_error, &log);
    RTCBVH bvh = rtcNewBVH(device);

    RTCBuildArguments args = rtcDefaultBuildArguments();
    args.buildQuality = high ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
    args.maxBranchingFactor = 8;
    args.maxDepth = 40;
    args.sahBlockSize = 4;
    args.minLeafSize = 4;
    args.maxLeafSize = 28;
    args.traversalCost = 1.0f;
    args.intersectionCost = 1.0f;
    args.bvh = bvh;
    args.primitives = prims.data();
    args.primitiveCount = count;
    args.primitiveArrayCapacity = prims.size();
    args.createNode = create_node;
    args.setNodeChildren = set_children;
    args.setNodeBounds = set_bounds;
    args.createLeaf = create_leaf;
    args.splitPrimitive = high ? split_primitive : nullptr;
    args.userPtr = const_cast<bvh8::ForeignTreeRequest*>(&request);

    const auto* root = static_cast<const Item*>(rtcBuildBVH(&args));
    bvh8::WideTree wide;
    std::string error;
    if (root)
        wide = copy_tree(root, root_box);
    else
        error = log.first_error.empty() ? "rtcBuildBVH returned no tree" : log.first_error;
    rtcReleaseBVH(bvh);
    rtcReleaseDevice(device);
    if (!error.empty()) throw Error("bvh8:tree=" + std::string(high ? "embree-high" : "embree-medium") + ": " + error);
    return wide;
}

}  // namespace

void install_embree_tree_builder() { bvh8::set_foreign_tree_builder(&build_with_embree); }

}  // namespace thicket
