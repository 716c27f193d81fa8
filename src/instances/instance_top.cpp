#include "thicket/instances/instance_top.h"

#include <algorithm>
#include <span>
#include <utility>

#include "thicket/bvh8/bvh8.h"
#include "thicket/bvh8/isa.h"
#include "thicket/prims/triangles.h"

namespace thicket {

namespace {

/// The bottom kernels of a triangle bvh8 of test T, if `accel` is one and has nodes.
template <TriangleTest T>
bool bvh8_bottom(const Accel& accel, InstanceBottom& out) {
    using B = Bvh8<Triangles<T>>;
    const auto* b = dynamic_cast<const B*>(&accel);
    if (!b || (b->tree().nodes.empty() && b->qnodes().empty())) return false;
    out.ctx = &b->trace_context();
    for (int c = 0; c < 2; ++c) {
        out.closest[c] = b->kernels().closest[B::kLeafKind][c];
        out.any[c] = b->kernels().any[B::kLeafKind][c];
    }
    return true;
}

/// ClosestLeafFn of the top level: each instance of the leaf tested below hit.t; a nearer hit
/// replaces hit with its flattened id (a tie keeps the instance found first).
bool closest_instances(const void* view, const uint32_t* ids, uint32_t count, const Ray& ray, Hit& hit) {
    const auto& v = *static_cast<const InstanceTop::View*>(view);
    bool found = false;
    for (const InstanceLeaf& leaf : std::span(v.leaves + (ids - v.ids), count)) {
        const Hit h = v.bottoms[leaf.bottom].closest_hit(leaf.to_local.ray(ray, hit.t), v.counters);
        if (h.found() && (!hit.found() || h.t < hit.t)) {
            hit = h;
            hit.prim = leaf.flat_first + h.prim;
            found = true;
        }
    }
    return found;
}

/// AnyLeafFn of the top level: whether any instance of the leaf is hit within the ray's interval.
bool any_instance(const void* view, const uint32_t* ids, uint32_t count, const Ray& ray) {
    const auto& v = *static_cast<const InstanceTop::View*>(view);
    for (const InstanceLeaf& leaf : std::span(v.leaves + (ids - v.ids), count))
        if (v.bottoms[leaf.bottom].any_hit(leaf.to_local.ray(ray, ray.tmax), v.counters)) return true;
    return false;
}

}  // namespace

Hit InstanceBottom::closest_hit(const Ray& local, RayCounters* counters) const {
    if (ctx) return closest[counters ? 1 : 0](*ctx, local, counters);
    return counters ? accel->intersect(local, *counters) : accel->intersect(local);
}

bool InstanceBottom::any_hit(const Ray& local, RayCounters* counters) const {
    if (ctx) return any[counters ? 1 : 0](*ctx, local, counters);
    return counters ? accel->occluded(local, *counters) : accel->occluded(local);
}

InstanceBottom instance_bottom(const Accel& accel) {
    InstanceBottom out;
    out.accel = &accel;
    if (!bvh8_bottom<TriangleTest::Moller>(accel, out)) bvh8_bottom<TriangleTest::Watertight>(accel, out);
    return out;
}

InstanceTop::InstanceTop(std::span<const Aabb> boxes, std::vector<InstanceLeaf> leaves,
                         std::vector<InstanceBottom> bottoms, unsigned threads)
    : leaves_(std::move(leaves)),
      bottoms_(std::move(bottoms)),
      kernels_(&bvh8::kernels_for(resolve_isa(kAutoIsa, "bvh8"))) {
    // Only instances a ray can hit take part; the builder sees them as primitives 0..n-1.
    std::vector<uint32_t> kept;
    std::vector<Aabb> kept_boxes;
    std::vector<Vec3> centroids;
    for (uint32_t i = 0; i < boxes.size(); ++i)
        if (!boxes[i].empty()) {
            kept.push_back(i);
            kept_boxes.push_back(boxes[i]);
            centroids.push_back(boxes[i].center());
        }
    if (!kept.empty()) {
        // One instance per leaf: a leaf costs a whole bottom-level traversal, so that a ray
        // should call only the instances whose own box it enters.
        BvhBuildOptions options;
        options.builder = BvhBuilder::BinnedSah;
        options.bins = 32;
        options.max_leaf = 1;
        options.sah_block = 1;
        options.threads = threads;
        const BvhData binary = build_bvh({kept_boxes, centroids, {}}, options);
        // The leaves' records in the tree's leaf order: a leaf reads its own slot, and the
        // instances a ray meets one after another lie side by side.
        std::vector<InstanceLeaf> ordered;
        ordered.reserve(binary.prim_indices.size());
        for (const uint32_t p : binary.prim_indices) {
            ids_.push_back(kept[p]);
            ordered.push_back(leaves_[kept[p]]);
        }
        leaves_ = std::move(ordered);
        tree_ = bvh8::collapse(
            binary, [](uint32_t first, uint32_t count) { return bvh8::LeafPlacement{first, count}; }, 1);
        bvh8::validate_tree(tree_, ids_.size());
    }
    view_ = {ids_.data(), leaves_.data(), bottoms_.data(), nullptr};
    ctx_ = {.nodes = tree_.nodes.data(),
            .qnodes = nullptr,
            .blocks = nullptr,
            .ids = ids_.data(),
            .prims = &view_,
            .closest_leaf = &closest_instances,
            .any_leaf = &any_instance};
    if (!tree_.nodes.empty()) bvh8::set_plane_bounds(ctx_, tree_.nodes.data(), tree_.nodes.size());
}

namespace {

/// kernel(ctx, counters) on the top level's context, or with counters on a copy whose leaves
/// count into *counters too: the counters travel to the leaves in a view of this call's own.
template <class Kernel>
auto counting_leaves(const bvh8::TraceContext& top, const InstanceTop::View& view, RayCounters* counters,
                     Kernel&& kernel) {
    if (!counters) return kernel(top, nullptr);
    InstanceTop::View counting = view;
    counting.counters = counters;
    bvh8::TraceContext ctx = top;
    ctx.prims = &counting;
    return kernel(ctx, counters);
}

}  // namespace

Hit InstanceTop::closest(const Ray& ray, RayCounters* counters) const {
    if (tree_.nodes.empty()) return miss_for(ray);
    return counting_leaves(ctx_, view_, counters, [&](const bvh8::TraceContext& ctx, RayCounters* c) {
        return kernels_->closest[bvh8::kLeafCallback][c ? 1 : 0](ctx, ray, c);
    });
}

bool InstanceTop::any(const Ray& ray, RayCounters* counters) const {
    if (tree_.nodes.empty()) return false;
    return counting_leaves(ctx_, view_, counters, [&](const bvh8::TraceContext& ctx, RayCounters* c) {
        return kernels_->any[bvh8::kLeafCallback][c ? 1 : 0](ctx, ray, c);
    });
}

}  // namespace thicket

namespace thicket {

std::vector<Aabb> vertex_parts(const Scene& scene, const Aabb& bounds) {
    const std::vector<Vec3>& v = scene.mesh.positions;
    if (scene.has_shapes() || v.empty()) return {bounds};
    constexpr int kDepth = 6;  // 64 parts: 512 corners per instance to transform at build time
    std::vector<uint32_t> order(v.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    struct Range {
        size_t begin, end;
        int depth;
    };
    std::vector<Range> todo{{0, order.size(), 0}};
    std::vector<Aabb> parts;
    while (!todo.empty()) {
        const Range r = todo.back();
        todo.pop_back();
        Aabb box;
        for (size_t k = r.begin; k < r.end; ++k) box.grow(v[order[k]]);
        if (r.depth == kDepth || r.end - r.begin <= 8) {
            parts.push_back(box);
            continue;
        }
        const Vec3 e = box.extent();
        const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
        const size_t mid = r.begin + (r.end - r.begin) / 2;
        std::nth_element(order.begin() + r.begin, order.begin() + mid, order.begin() + r.end,
                         [&](uint32_t a, uint32_t b) { return v[a][axis] < v[b][axis]; });
        todo.push_back({r.begin, mid, r.depth + 1});
        todo.push_back({mid, r.end, r.depth + 1});
    }
    return parts;
}

Aabb transform_parts(const Affine& t, std::span<const Aabb> parts) {
    Aabb out;
    for (const Aabb& p : parts) out.grow(transform_box(t, p));
    return out;
}

}  // namespace thicket
