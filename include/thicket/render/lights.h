#pragma once
/// Light sampling for next event estimation: every emissive triangle and sphere of a RenderScene
/// and its point lights, one of them chosen in proportion to its emitted power, then a point on
/// it (triangles: uniform in area; spheres: uniform in the cone they subtend from outside, uniform
/// in area from inside). pdf() gives the density of the same choice for a direction found by
/// BSDF sampling, which multiple importance sampling weighs against the BSDF's density.
#include <cstdint>
#include <vector>

#include "thicket/render/render_scene.h"

namespace thicket {

/// One sampled light direction from a shading point.
struct LightSample {
    Vec3 wi;              ///< unit direction from the shading point to the light
    float distance = 0;   ///< to the sampled point (shadow rays stop short of it)
    Vec3 radiance;        ///< emitted radiance toward the point (for a point light: intensity / d^2)
    float pdf = 0;        ///< solid-angle density times the choice probability (a point light: the probability)
    bool delta = false;   ///< a point light (no BSDF sample can find it)
};

class LightSet {
public:
    /// Collects the lights of `rs`: primitives whose material emits (triangles and spheres; other
    /// shapes are not sampled, they only glow when hit) and the point lights.
    explicit LightSet(const RenderScene& rs);

    bool empty() const { return cdf_.empty(); }
    size_t size() const { return lights_.size(); }

    /// A light direction from point `p` from three uniform numbers. False when the sample carries
    /// nothing (no lights, the back of a one-sided emitter).
    bool sample(Vec3 p, float u_pick, float u0, float u1, LightSample& out) const;
    /// The density sample() gives to direction `wi` from `p` reaching primitive `prim` at point `y`
    /// with unit geometric normal `n_y`; 0 when prim is not a sampled light.
    float pdf(Vec3 p, Vec3 wi, uint32_t prim, Vec3 y, Vec3 n_y) const;

private:
    enum class Kind : uint8_t { Triangle, Sphere, Point };
    struct Light {
        Kind kind;
        uint32_t prim;           // primitive id (Triangle, Sphere); unused for Point
        Vec3 a, e1, e2;          // Triangle: corner and edges; Sphere: a = centre; Point: a = position
        float radius_or_area;    // Sphere radius or Triangle area
        Vec3 radiance;           // emitted radiance, or a point light's intensity
        bool two_sided;
    };
    float pick_probability(size_t light) const;

    std::vector<Light> lights_;
    std::vector<float> cdf_;                  // running sum of power, normalised to end at 1
    std::vector<uint32_t> light_of_prim_;     // light index per primitive id, or kNoPrim
};

}  // namespace thicket
