#pragma once
/// The one table of material parameters that every material reader applies: the OBJ reader's MTL
/// statements, glTF's material properties and the JSON scene's `materials` (docs/rendering.md,
/// "Material parameters"). Each entry names the parameter as each format spells it and the closed
/// range its values must lie in; a reader refuses a value outside with an Error that names the
/// file and line (MTL) or JSON path (JSON, glTF) followed by material_value_problem()'s text, so a
/// value is accepted or refused, with the same words, whichever format carries it.
#include <cstdint>
#include <span>
#include <string>

#include "thicket/geometry/mesh.h"

namespace thicket {

/// The largest emitted radiance (per channel) a material may have. With it, an emitter's power
/// pi * area * radiance stays finite in double for any triangle or sphere of float coordinates
/// (area < 1e78), and so does the total over 2^32 emitters, which light selection by power needs.
inline constexpr double kMaxEmission = 1e6;
/// The largest Phong exponent (MTL Ns): far beyond a mirror-like lobe (Ns >= 1000 is a mirror).
inline constexpr double kMaxShininess = 1e6;

enum class MaterialParam : uint8_t {
    Diffuse,           ///< Kd, kd, baseColorFactor[0..2]
    Specular,          ///< Ks, ks
    Emission,          ///< Ke, ke, emissiveFactor (and emissiveFactor x emissiveStrength)
    EmissiveStrength,  ///< glTF KHR_materials_emissive_strength
    Shininess,         ///< Ns, ns
    Ior,               ///< Ni, ni, KHR_materials_ior
    Dissolve,          ///< d (and glTF baseColorFactor[3], alpha)
    Transparency,      ///< Tr, KHR_materials_transmission (1 - d)
    Illum,             ///< illum
    Metallic,          ///< glTF metallicFactor
    Roughness,         ///< glTF roughnessFactor
};

struct MaterialRange {
    MaterialParam param;
    const char* what;  ///< what the parameter is, for messages and docs
    const char* mtl;   ///< the MTL statement, or "" when MTL has none
    const char* json;  ///< the JSON scene's material key, or ""
    const char* gltf;  ///< the glTF property (path inside a material), or ""
    double lo, hi;     ///< the accepted values, both ends included
    bool integer;      ///< only whole numbers
};

/// Every entry, in the order of MaterialParam.
std::span<const MaterialRange> material_ranges();
/// The entry of `p`.
const MaterialRange& material_range(MaterialParam p);

/// "" when `value` is accepted for `p`; else why not, as "must be <range> (<what>), got <value>",
/// e.g. "must be a number from 0 to 1 (diffuse reflectance), got inf". Readers put the location
/// and the parameter's name in front.
std::string material_value_problem(MaterialParam p, double value);

/// The first parameter of `m` outside the table, as "<MTL name>[channel]: <problem>" (e.g.
/// "Ke[0]: must be ..."); "" when every one is in range. For materials made in code (the readers
/// have refused such values already): make_render_scene() refuses them with the material's name.
/// An `illum` of -1 (none given) is accepted.
std::string material_problem(const Material& m);

}  // namespace thicket
