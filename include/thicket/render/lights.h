#pragma once
/// Light sampling for next event estimation: every emissive triangle and sphere of a RenderScene
/// and its point lights, one of them chosen in proportion to its emitted power, then a point on
/// it (triangles: uniform in area; spheres: uniform in the cone they subtend from outside, uniform
/// in area from inside). pdf() gives the density of the same choice for a direction found by
/// BSDF sampling, which multiple importance sampling weighs against the BSDF's density.
#include <cstdint>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/render/render_scene.h"

namespace thicket {

/// The largest point-light intensity (W/sr, per channel) the renderer takes: 1e20 lights a surface
/// 1e7 units away as brightly as a radiance-1 sky, and still leaves every sample finite in float.
inline constexpr double kMaxPointIntensity = 1e20;

/// Throws Error unless every material of `rs` emits a radiance each of whose channels is a number
/// from 0 to kMaxEmission (thicket/scene/material_ranges.h), and every point light an intensity
/// from 0 to kMaxPointIntensity; the message names the material (its name, else its index) or the
/// light. The readers refuse such values already; this holds materials made in code to the same
/// bound, so light selection's total power is finite for every scene the renderer accepts.
void check_emitters(const RenderScene& rs);

/// When nothing in `rs` is a light LightSet samples (no emissive triangle or sphere, no point
/// light), adds one point light for `camera` and returns a one-line description of it, which is
/// also written to stderr; otherwise returns "" and leaves `rs` as it is. The light sits at the
/// camera, raised by 5% of d along the camera's up vector, with intensity 2 d^2, where d is the
/// 25th percentile of the distances at which a 32 x 32 grid of camera rays over a width x height
/// image hits the scene (through `accel`, built over rs.scene): a white Lambertian surface facing
/// the light at distance d then has radiance 0.5, and only the nearest quarter of what the camera
/// sees is brighter, whatever the size of the scene's bounds (docs/rendering.md). When no probe ray
/// hits anything, d is the distance from the camera to the centre of the scene's bounds.
std::string add_automatic_light(RenderScene& rs, const Accel& accel, const Camera& camera, int width, int height);

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
    /// shapes are not sampled, they only glow when hit, and stderr says so once per material) and
    /// the point lights. Throws Error as check_emitters() does.
    explicit LightSet(const RenderScene& rs);

    bool empty() const { return cdf_.empty(); }
    size_t size() const { return lights_.size(); }
    /// The sum of every light's power that the choice is proportional to (pi x area x luminance
    /// for emitters, 4 pi x luminance for point lights); finite for every scene LightSet accepts.
    double total_power() const { return total_power_; }

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
    double total_power_ = 0.0;
    std::vector<uint32_t> light_of_prim_;     // light index per primitive id, or kNoPrim
};

}  // namespace thicket
