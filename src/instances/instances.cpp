#include "thicket/instances/instances.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket {

Scene geometry_scene(const Scene& scene, uint32_t geometry) {
    if (geometry >= scene.geometry_count())
        throw Error("scene '" + scene.name + "' has no geometry " + std::to_string(geometry) + " (it has " +
                    std::to_string(scene.geometry_count()) + ")");
    const Geometry g = scene.geometry(geometry);
    Scene out;
    out.name = scene.name + " geometry " + std::to_string(geometry);
    if (g.count == 0) return out;
    const PrimRef first = scene.locate(g.first);
    if (first.shape) {
        out.add_shapes(std::span<const Shape>(scene.shapes.data() + first.index, g.count));
        return out;
    }
    TriangleMesh m;
    m.positions.assign(scene.mesh.positions.begin() + g.vertex_first,
                       scene.mesh.positions.begin() + g.vertex_first + g.vertex_count);
    m.indices.reserve(size_t(3) * g.count);
    for (size_t i = 3 * size_t(first.index); i < 3 * (size_t(first.index) + g.count); ++i)
        m.indices.push_back(scene.mesh.indices[i] - g.vertex_first);
    out.add_mesh(m);
    return out;
}

std::unique_ptr<Accel> build_instanced(const Scene& scene, const AccelSpec& bottom) {
    auto prototypes = std::make_shared<Scene>(scene);
    prototypes->instances.clear();
    prototypes->instance_first.clear();
    return std::make_unique<InstancedAccel>(std::move(prototypes), scene.instances, bottom.str(), bottom.threads);
}

Scene flatten_instances(const Scene& prototypes, const std::vector<Instance>& instances) {
    Scene out;
    out.name = prototypes.name + " (flattened)";
    for (size_t i = 0; i < instances.size(); ++i) {
        Scene g = geometry_scene(prototypes, instances[i].geometry);
        if (g.has_shapes())
            throw Error("instance " + std::to_string(i) + ": geometry " + std::to_string(instances[i].geometry) +
                        " holds shapes, which cannot be flattened (a transformed shape is another shape)");
        for (Vec3& p : g.mesh.positions) p = instances[i].transform.point(p);
        out.add_mesh(g.mesh);
    }
    return out;
}

void InstancedAccel::check_instances(const std::vector<Instance>& instances, std::vector<Affine>& inverses,
                                     std::vector<uint64_t>& flat_first) const {
    inverses.clear();
    flat_first.assign(1, 0);
    const size_t geometries = prototypes_->geometry_count();
    for (size_t i = 0; i < instances.size(); ++i) {
        const std::string what = "instance " + std::to_string(i);
        if (instances[i].geometry >= geometries)
            throw Error(what + ": scene '" + prototypes_->name + "' has no geometry " +
                        std::to_string(instances[i].geometry) + " (it has " + std::to_string(geometries) + ")");
        inverses.push_back(checked_inverse(instances[i].transform, what));
        flat_first.push_back(flat_first.back() + prototypes_->geometry(instances[i].geometry).count);
    }
    // kNoPrim means a miss, so the last usable flattened id is kNoPrim - 1.
    if (flat_first.back() >= kNoPrim)
        throw Error("the instances hold " + std::to_string(flat_first.back()) +
                    " primitives in all; at most " + std::to_string(kNoPrim - 1) +
                    " can be told apart by a hit's 32-bit primitive id");
}

InstancedAccel::InstancedAccel(std::shared_ptr<const Scene> prototypes, std::vector<Instance> instances,
                               std::string_view bottom_spec, unsigned threads)
    : prototypes_(std::move(prototypes)), bottom_spec_(parse_accel_spec(bottom_spec).str()) {
    if (!prototypes_) throw Error("instanced structure: no prototype scene");
    check_instances(instances, inverses_, flat_first_);
    instances_ = std::move(instances);
    bottoms_.resize(prototypes_->geometry_count());
    parts_.resize(prototypes_->geometry_count());
    for (const Instance& inst : instances_) build_bottom(inst.geometry, threads);
    build_top();
    set_origin(bottom_spec_, 0.0);
}

void InstancedAccel::build_bottom(uint32_t geometry, unsigned threads) {
    if (bottoms_[geometry]) return;
    const Scene scene = geometry_scene(*prototypes_, geometry);
    bottoms_[geometry] = build_accel(bottom_spec_, scene, threads);
    parts_[geometry] = vertex_parts(scene, bottoms_[geometry]->bounds());
}

uint32_t InstancedAccel::add_instance(const Instance& instance) {
    // Only the new instance is checked (the others were), so that adding n costs O(n) checks.
    const std::string what = "instance " + std::to_string(instances_.size());
    if (instance.geometry >= prototypes_->geometry_count())
        throw Error(what + ": scene '" + prototypes_->name + "' has no geometry " + std::to_string(instance.geometry) +
                    " (it has " + std::to_string(prototypes_->geometry_count()) + ")");
    const Affine inverse = checked_inverse(instance.transform, what);
    const uint64_t end = flat_first_.back() + prototypes_->geometry(instance.geometry).count;
    if (end >= kNoPrim)
        throw Error(what + ": the instances would hold " + std::to_string(end) + " primitives in all; at most " +
                    std::to_string(kNoPrim - 1) + " can be told apart by a hit's 32-bit primitive id");
    build_bottom(instance.geometry, 0);
    instances_.push_back(instance);
    inverses_.push_back(inverse);
    flat_first_.push_back(end);
    try {
        build_top();
    } catch (...) {
        instances_.pop_back();
        inverses_.pop_back();
        flat_first_.pop_back();
        build_top();
        throw;
    }
    return uint32_t(instances_.size() - 1);
}

void InstancedAccel::set_transform(uint32_t id, const Affine& transform) {
    if (id >= instances_.size())
        throw Error("set_transform: no instance " + std::to_string(id) + " (there are " +
                    std::to_string(instances_.size()) + ")");
    const Affine inverse = checked_inverse(transform, "instance " + std::to_string(id));
    const Instance before = instances_[id];
    const Affine inverse_before = inverses_[id];
    inverses_[id] = inverse;
    instances_[id].transform = transform;
    try {
        build_top();
    } catch (...) {  // a transform that carries the geometry beyond float range
        instances_[id] = before;
        inverses_[id] = inverse_before;
        build_top();
        throw;
    }
}

void InstancedAccel::build_top() {
    const auto n = uint32_t(instances_.size());
    world_boxes_.resize(n);
    std::vector<InstanceLeaf> leaves(n);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t g = instances_[i].geometry;
        world_boxes_[i] = transform_parts(instances_[i].transform, parts_[g]);
        for (int a = 0; a < 3; ++a)
            if (!world_boxes_[i].empty() && (!std::isfinite(world_boxes_[i].min[a]) || !std::isfinite(world_boxes_[i].max[a])))
                throw Error("instance " + std::to_string(i) + ": its transform carries the geometry beyond float range");
        leaves[i] = {ray_to_instance(instances_[i].transform, inverses_[i]), uint32_t(flat_first_[i]), g};
    }
    std::vector<InstanceBottom> bottoms(bottoms_.size());
    for (size_t g = 0; g < bottoms_.size(); ++g)
        if (bottoms_[g]) bottoms[g] = instance_bottom(*bottoms_[g]);
    top_ = std::make_unique<const InstanceTop>(world_boxes_, std::move(leaves), std::move(bottoms), 0);
}

Hit InstancedAccel::intersect(const Ray& ray) const { return top_->closest(ray, nullptr); }
Hit InstancedAccel::intersect(const Ray& ray, RayCounters& counters) const { return top_->closest(ray, &counters); }
bool InstancedAccel::occluded(const Ray& ray) const { return top_->any(ray, nullptr); }
bool InstancedAccel::occluded(const Ray& ray, RayCounters& counters) const { return top_->any(ray, &counters); }

Aabb InstancedAccel::bounds() const { return top_->bounds(); }

InstanceHit InstancedAccel::locate(uint32_t prim) const {
    InstanceHit r;
    if (prim == kNoPrim || prim >= instanced_primitives()) return r;
    const auto it = std::upper_bound(flat_first_.begin(), flat_first_.end(), uint64_t(prim));
    r.instance = uint32_t(it - flat_first_.begin()) - 1;
    r.geometry = instances_[r.instance].geometry;
    r.prim = uint32_t(prim - flat_first_[r.instance]);
    r.scene_prim = prototypes_->geometry(r.geometry).first + r.prim;
    return r;
}

Vec3 InstancedAccel::normal(const Ray& ray, const Hit& hit) const {
    const InstanceHit where = locate(hit.prim);
    if (where.instance == kNoPrim) return Vec3{};
    const Affine& inv = inverses_[where.instance];
    Hit local = hit;
    local.prim = where.scene_prim;
    const RayToInstance to_local = ray_to_instance(instances_[where.instance].transform, inv);
    const Vec3 n = prototypes_->normal(to_local.ray(ray, ray.tmax), local);
    Vec3 w = inv.transposed_vector(n);
    if (!prototypes_->locate(where.scene_prim).shape && transform_determinant(instances_[where.instance].transform) < 0.0)
        w = -w;
    const float len = length(w);
    if (!(len > 0.0f) || !std::isfinite(len)) return Vec3{};
    return w / len;
}

size_t InstancedAccel::unique_primitives() const {
    size_t n = 0;
    for (uint32_t g = 0; g < bottoms_.size(); ++g)
        if (bottoms_[g]) n += prototypes_->geometry(g).count;
    return n;
}

AccelStats InstancedAccel::stats() const {
    AccelStats s = base_stats();
    s.primitives = instanced_primitives();
    s.nodes = top_->node_count();
    size_t geometries = 0;
    for (const auto& b : bottoms_)
        if (b) {
            const AccelStats bs = b->stats();
            s.nodes += bs.nodes;
            s.bytes += bs.bytes;
            s.primitive_bytes += bs.primitive_bytes;
            ++geometries;
        }
    // What is held per instance: its placement, inverse, flattened id, world box, and the top
    // level's copy of what a leaf reads (InstanceTop::bytes).
    s.bytes += top_->bytes() + instances_.size() * sizeof(Instance) + inverses_.size() * sizeof(Affine) +
               flat_first_.size() * sizeof(uint64_t) + world_boxes_.size() * sizeof(Aabb);
    s.extra.emplace_back(kSahUndefinedKey, "two levels: each bottom level has its own SAH cost");
    s.extra.emplace_back("instanced", "two levels: a top-level 8-wide BVH over the instances, this spec below");
    s.extra.emplace_back("instances", std::to_string(instances_.size()));
    s.extra.emplace_back("geometries instanced", std::to_string(geometries));
    s.extra.emplace_back("unique primitives", std::to_string(unique_primitives()));
    s.extra.emplace_back("instanced primitives", std::to_string(instanced_primitives()));
    return s;
}

void InstancedAccel::refit(const Scene&, unsigned) {
    throw Error(spec() + ": an instanced structure is not refitted: move instances with set_transform, and build a "
                         "new one when the prototype geometry moves");
}

void InstancedAccel::save(std::ostream&) const {
    throw Error(spec() + ": a structure over a scene with instances cannot be saved to a file; a glTF scene whose "
                         "nodes share a mesh loads as instances, and loaded with --flatten (one triangle soup) its "
                         "structure can be saved");
}

}  // namespace thicket
