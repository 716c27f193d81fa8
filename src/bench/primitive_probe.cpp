#include "thicket/bench/primitive_probe.h"

#include <cmath>
#include <memory>
#include <tuple>

#include "thicket/prims/mixed.h"
#include "thicket/prims/triangles.h"

namespace thicket {

namespace {

template <class Prims>
std::function<Hit(uint32_t, const Ray&)> probe_of(Prims prims) {
    auto shared = std::make_shared<const Prims>(std::move(prims));
    return [shared](uint32_t prim, const Ray& ray) {
        Hit hit = miss_for(ray);
        return shared->intersect(prim, ray, hit) ? hit : Hit{};
    };
}

}  // namespace

PrimitiveProbe::PrimitiveProbe(const Scene& scene, const std::string& isect) : count_(scene.primitive_count()) {
    if (!scene.instances.empty()) {
        // Flattened ids: the prototype's primitive, probed with the ray in its instance's space,
        // as the instanced structure tests it (instances/instances.h), so the answers are the same bits.
        auto prototypes = std::make_shared<Scene>(scene);
        prototypes->instances.clear();
        prototypes->instance_first.clear();
        auto inner = std::make_shared<const PrimitiveProbe>(*prototypes, isect);
        count_ = size_t(scene.instanced_primitive_count());
        hit_ = [prototypes, inner, &scene](uint32_t prim, const Ray& ray) {
            InstancePlace place;
            if (!place_instanced_hit(scene, ray, Hit{0.0f, 0.0f, 0.0f, prim}, place)) return Hit{};
            Hit h = inner->hit(place.hit.prim, place.ray);
            if (h.found()) h.prim = prim;
            return h;
        };
        return;
    }
    const bool watertight = isect == "watertight";
    if (scene.has_shapes()) {
        const auto& [mesh, shapes, runs, name] = std::tie(scene.mesh, scene.shapes, scene.runs, scene.name);
        hit_ = probe_of(MixedPrimitives(mesh, shapes, runs, name,
                                        watertight ? TriangleTest::Watertight : TriangleTest::Moller));
        return;
    }
    hit_ = watertight ? probe_of(Triangles<TriangleTest::Watertight>(scene.mesh))
                      : probe_of(Triangles<TriangleTest::Moller>(scene.mesh));
}

PrimitiveProbe::PrimitiveProbe(const TriangleMesh& mesh, const std::string& isect) : count_(mesh.triangle_count()) {
    hit_ = isect == "watertight" ? probe_of(Triangles<TriangleTest::Watertight>(mesh))
                                 : probe_of(Triangles<TriangleTest::Moller>(mesh));
}

Hit PrimitiveProbe::hit(uint32_t prim, const Ray& ray) const {
    if (prim >= count_) return Hit{};
    return hit_(prim, ray);
}

bool identical_hits(const Hit& a, const Hit& b) {
    if (a.found() != b.found()) return false;
    if (!a.found()) return true;
    return a.prim == b.prim && a.t == b.t && a.u == b.u && a.v == b.v;
}

}  // namespace thicket
