#pragma once
/// The surface materials of the light-transport integrators and their BSDFs: Lambertian
/// (cosine-sampled), ideal mirror, glossy (Lambert plus a normalised modified-Phong lobe, bounded
/// so that no direction reflects more than it receives) and smooth dielectric (exact unpolarised
/// Fresnel, total internal reflection). Directions are unit vectors pointing away from the
/// surface; `n` is the surface's geometric normal (for a dielectric the outward one: the side
/// it points to is outside, index of refraction 1).
#include <string>

#include "thicket/core/vec3.h"
#include "thicket/geometry/mesh.h"

namespace thicket {

enum class SurfaceKind {
    Lambert,     ///< albedo / pi
    Mirror,      ///< perfect reflection, tinted by `specular`
    Glossy,      ///< albedo / pi + specular (e + 2) / (2 pi) cos^e(angle to the mirror direction)
    Dielectric,  ///< glass: Fresnel-weighted reflection and refraction with index `ior`
};

struct SurfaceMaterial {
    SurfaceKind kind = SurfaceKind::Lambert;
    Vec3 albedo{0.8f, 0.8f, 0.8f};   ///< diffuse reflectance (Lambert, Glossy)
    Vec3 specular{1.0f, 1.0f, 1.0f}; ///< mirror reflectance, or the glossy lobe's weight
    float exponent = 50.0f;          ///< glossy lobe's Phong exponent (>= 0)
    float ior = 1.5f;                ///< dielectric: index of refraction inside (outside is 1)
    Vec3 emission{};                 ///< radiance emitted (area lights); zero for most surfaces
    bool two_sided = false;          ///< emits on both sides (spheres); else only where n points
    std::string name;                ///< the source material's name, for messages; may be empty

    /// Whether the BSDF is a Dirac delta (mirror, dielectric): no light sampling through it.
    bool delta() const { return kind == SurfaceKind::Mirror || kind == SurfaceKind::Dielectric; }
    bool emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
    /// Whether it reflects or transmits anything (a pure black emitter ends paths).
    bool scatters() const;
};

/// A Lambertian material of reflectance `albedo` (clamped to [0, 1]).
SurfaceMaterial lambert(Vec3 albedo, Vec3 emission = {});
/// A mirror of reflectance `tint` (clamped to [0, 1]).
SurfaceMaterial mirror(Vec3 tint = Vec3{1.0f});
/// A glossy material; albedo and specular are scaled down together wherever their sum exceeds 1
/// in a channel, so the material is energy-bounded whatever it is given.
SurfaceMaterial glossy(Vec3 albedo, Vec3 specular, float exponent);
/// A smooth dielectric of index `ior` (> 0, != 1 for any refraction to show).
SurfaceMaterial dielectric(float ior);

/// The nearest SurfaceMaterial to an OBJ/MTL-style Material: emission Ke carries over; a
/// dissolve d < 1 or illum 4, 6, 7 with Ni != 1 gives a dielectric of index Ni; illum 3 or 5, or
/// Ns >= 1000 with a non-zero Ks, a mirror of reflectance Ks; another non-zero Ks a glossy
/// material with exponent Ns; otherwise Lambertian with albedo Kd.
SurfaceMaterial surface_from_material(const Material& m);

/// Unpolarised Fresnel reflectance of a smooth interface for light arriving at cosine `cos_i`
/// (>= 0, from the side of index n_i) where eta = n_t / n_i. 1 under total internal reflection.
float fresnel_dielectric(float cos_i, float eta);
/// The transmittance of the same interface from the Fresnel transmission amplitudes
/// (eta cos_t / cos_i) (t_s^2 + t_p^2) / 2, computed independently of fresnel_dielectric so that
/// R + T = 1 is a check; 0 under total internal reflection.
float fresnel_transmittance(float cos_i, float eta);

/// A sampled direction: wi, the estimator weight f |cos| / pdf, the density (solid angle; for a
/// delta lobe the probability of choosing it) and whether it came from a delta lobe.
struct BsdfSample {
    Vec3 wi;
    Vec3 weight;
    float pdf = 0.0f;
    bool delta = false;
};

/// Samples an incident direction for outgoing `wo` at a surface with normal `n`, from three
/// uniform numbers. False when the sample carries no energy (below the surface, zero weight).
bool sample_bsdf(const SurfaceMaterial& m, Vec3 n, Vec3 wo, float u0, float u1, float u2, BsdfSample& out);
/// f(wo, wi) |cos(n, wi)| for the non-delta part of the BSDF (zero for mirror and dielectric).
Vec3 eval_bsdf(const SurfaceMaterial& m, Vec3 n, Vec3 wo, Vec3 wi);
/// The solid-angle density with which sample_bsdf() picks wi given wo (0 for delta materials).
float pdf_bsdf(const SurfaceMaterial& m, Vec3 n, Vec3 wo, Vec3 wi);

}  // namespace thicket
