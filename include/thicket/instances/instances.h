#pragma once
/// Two-level instancing: a top-level 8-wide BVH over instances (instances/instance_top.h), each a
/// geometry of a prototype scene under an affine transform, over one bottom-level structure (any
/// registered spec) per geometry that some instance references, built once however many
/// instances share it. Memory grows with the unique geometry; moving instances (set_transform)
/// rebuilds only the top level.
///
/// Rays are carried into each instance's space by its inverse transform; the ray parameter t is
/// unchanged by an affine map, so hits' t are in the world ray's units. Through the Accel
/// interface a hit's `prim` is its id in the flattened scene (flatten_instances(): every
/// instance's primitives, instance by instance, in geometry order), so every query, batch, bench
/// and agreement check of Accel works unchanged; locate() turns such an id into the instance, the
/// geometry and the primitive within the geometry (Hit keeps its 16-byte layout). Its spec() is
/// the bottom level's, so that whatever reads a structure's spec reads the one that was asked
/// for; stats().extra says it is instanced.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/instances/instance_top.h"
#include "thicket/accel/registry.h"
#include "thicket/scene/instance.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// What a flattened primitive id stands for. All kNoPrim for a miss.
struct InstanceHit {
    uint32_t instance = kNoPrim;  ///< index into the instances
    uint32_t geometry = kNoPrim;  ///< the prototype scene's geometry id
    uint32_t prim = kNoPrim;      ///< the primitive within the geometry (0-based)
    uint32_t scene_prim = kNoPrim;///< its id in the prototype scene (materials, Scene::locate)
};

class InstancedAccel final : public Accel {
public:
    /// Builds a `bottom_spec` structure over each geometry of `prototypes` that an instance
    /// references (on up to `threads` threads, 0: all cores) and the top level over the
    /// instances. Throws Error for a bad spec, an instance naming a geometry the scene does not
    /// have, a near-singular or non-finite transform (checked_inverse), or more than 2^32 - 2
    /// instanced primitives in all (flattened ids are 32-bit).
    InstancedAccel(std::shared_ptr<const Scene> prototypes, std::vector<Instance> instances,
                   std::string_view bottom_spec, unsigned threads = 0);

    /// Appends an instance (building the geometry's bottom level if no instance used it yet) and
    /// rebuilds the top level; returns its id. On Error nothing changes.
    uint32_t add_instance(const Instance& instance);
    /// Replaces instance `id`'s transform and rebuilds only the top level. Throws Error (nothing
    /// changed) for an id out of range or a transform checked_inverse refuses.
    void set_transform(uint32_t id, const Affine& transform);

    /// The instance, geometry and primitive behind the flattened id `prim` (a Hit's prim).
    InstanceHit locate(uint32_t prim) const;
    /// Unit world-space normal at `hit` of the world ray `ray`: the prototype's normal
    /// (Scene::normal) carried by the inverse transpose; a triangle's, which follows the winding
    /// order, is flipped under a mirroring transform as the transformed triangle's winding is.
    /// Zero where the prototype has none.
    Vec3 normal(const Ray& ray, const Hit& hit) const;

    const Scene& prototypes() const { return *prototypes_; }
    const std::vector<Instance>& instances() const { return instances_; }
    /// Primitives of the geometries some instance references, each counted once.
    size_t unique_primitives() const;
    /// Primitives of every instance (the flattened scene's size).
    size_t instanced_primitives() const { return flat_first_.empty() ? 0 : flat_first_.back(); }
    /// The bottom-level structure of geometry `geometry`; null if no instance references it.
    const Accel* bottom(uint32_t geometry) const { return bottoms_.at(geometry).get(); }
    /// The top level: its tree over the instances' world boxes.
    const InstanceTop& top() const { return *top_; }
    /// Instance `id`'s world box as the top level holds it (empty for empty geometry).
    const Aabb& world_box(uint32_t id) const { return world_boxes_.at(id); }

    using Accel::intersect;  // the batch overloads stay visible next to the per-ray ones
    using Accel::occluded;
    Aabb bounds() const override;
    Hit intersect(const Ray& ray) const override;
    Hit intersect(const Ray& ray, RayCounters& counters) const override;
    bool occluded(const Ray& ray) const override;
    bool occluded(const Ray& ray, RayCounters& counters) const override;
    /// Figures of the whole: sizes are the top level's plus every bottom level's once;
    /// `extra` gives instances, geometries, unique and instanced primitives.
    AccelStats stats() const override;
    /// Throws Error: move instances with set_transform(); a moved prototype needs a new structure.
    void refit(const Scene& scene, unsigned threads = 0) override;
    /// Throws Error: an instanced structure has no file format yet; the message names the way out
    /// for a glTF scene (loaded flattened, its structure can be saved).
    void save(std::ostream& out) const override;

private:
    void build_bottom(uint32_t geometry, unsigned threads);
    void build_top();
    /// The inverses and flattened ids of instances_ (throws, leaving members unchanged).
    void check_instances(const std::vector<Instance>& instances, std::vector<Affine>& inverses,
                         std::vector<uint64_t>& flat_first) const;

    std::shared_ptr<const Scene> prototypes_;
    std::string bottom_spec_;
    std::vector<Instance> instances_;
    std::vector<Affine> inverses_;
    std::vector<uint64_t> flat_first_;  ///< instances + 1 entries: flattened id of each one's first primitive
    std::vector<std::shared_ptr<const Accel>> bottoms_;  ///< per geometry of prototypes_
    std::vector<std::vector<Aabb>> parts_;  ///< per geometry of prototypes_: vertex_parts of what bottoms_ holds
    std::vector<Aabb> world_boxes_;
    std::unique_ptr<const InstanceTop> top_;
};

/// What build_accel() builds over a scene with instances: an InstancedAccel over a copy of the
/// scene without them (the prototypes) and its instances, `bottom` the bottom level's spec.
std::unique_ptr<Accel> build_instanced(const Scene& scene, const AccelSpec& bottom);

/// The flattened scene: every instance's geometry with the transform applied to its vertices,
/// instance by instance, one geometry each (shapes are refused with Error: a transformed sphere is
/// no sphere). What an instanced structure's answers are checked against.
Scene flatten_instances(const Scene& prototypes, const std::vector<Instance>& instances);

/// The scene holding only geometry `geometry` of `scene` (its primitives as ids 0..count-1, a
/// mesh's vertices renumbered from 0; materials are not carried), as a bottom level is built over.
Scene geometry_scene(const Scene& scene, uint32_t geometry);

}  // namespace thicket
