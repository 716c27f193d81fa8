// The material parameter table (material_ranges.h). Ranges follow what the renderer can use and
// what the formats define: reflectances are fractions (more than 1 would create light), an index
// of refraction is MTL's 0.001..10 (below 1: the inside is optically thinner than the outside, as
// an air bubble in water; the dielectric handles it), emission is bounded so light power stays
// finite, and illum is one of MTL's eleven models.
#include "thicket/scene/material_ranges.h"

#include <cmath>
#include <cstdio>

#include "thicket/core/error.h"

namespace thicket {

namespace {

constexpr MaterialRange kTable[] = {
    {MaterialParam::Diffuse, "diffuse reflectance", "Kd", "kd", "pbrMetallicRoughness.baseColorFactor", 0, 1, false},
    {MaterialParam::Specular, "specular reflectance", "Ks", "ks", "", 0, 1, false},
    {MaterialParam::Emission, "emitted radiance", "Ke", "ke", "emissiveFactor", 0, kMaxEmission, false},
    {MaterialParam::EmissiveStrength, "emission strength", "", "",
     "extensions.KHR_materials_emissive_strength.emissiveStrength", 0, kMaxEmission, false},
    {MaterialParam::Shininess, "Phong exponent", "Ns", "ns", "", 0, kMaxShininess, false},
    {MaterialParam::Ior, "index of refraction", "Ni", "ni", "extensions.KHR_materials_ior.ior", 0.001, 10, false},
    {MaterialParam::Dissolve, "opacity", "d", "d", "pbrMetallicRoughness.baseColorFactor[3]", 0, 1, false},
    {MaterialParam::Transparency, "transparency", "Tr", "",
     "extensions.KHR_materials_transmission.transmissionFactor", 0, 1, false},
    {MaterialParam::Illum, "illumination model", "illum", "illum", "", 0, 10, true},
    {MaterialParam::Metallic, "metalness", "", "", "pbrMetallicRoughness.metallicFactor", 0, 1, false},
    {MaterialParam::Roughness, "roughness", "", "", "pbrMetallicRoughness.roughnessFactor", 0, 1, false},
};

std::string number_text(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

}  // namespace

std::span<const MaterialRange> material_ranges() { return kTable; }

const MaterialRange& material_range(MaterialParam p) {
    const size_t i = size_t(p);
    if (i >= std::size(kTable) || kTable[i].param != p) throw Error("material_range: unknown parameter");
    return kTable[i];
}

std::string material_value_problem(MaterialParam p, double value) {
    const MaterialRange& r = material_range(p);
    // NaN fails both comparisons, so it is refused with the infinities.
    const bool inside = value >= r.lo && value <= r.hi && (!r.integer || std::floor(value) == value);
    if (inside) return "";
    return std::string("must be ") + (r.integer ? "a whole number" : "a number") + " from " + number_text(r.lo) +
           " to " + number_text(r.hi) + " (" + r.what + "), got " + number_text(value);
}

std::string material_problem(const Material& m) {
    auto colour = [](MaterialParam p, Vec3 c) -> std::string {
        for (int i = 0; i < 3; ++i)
            if (std::string why = material_value_problem(p, c[i]); !why.empty())
                return std::string(material_range(p).mtl) + "[" + std::to_string(i) + "]: " + why;
        return "";
    };
    auto scalar = [](MaterialParam p, double v) -> std::string {
        const std::string why = material_value_problem(p, v);
        return why.empty() ? "" : std::string(material_range(p).mtl) + ": " + why;
    };
    for (const std::string& why :
         {colour(MaterialParam::Diffuse, m.diffuse), colour(MaterialParam::Specular, m.specular),
          colour(MaterialParam::Emission, m.emission), scalar(MaterialParam::Shininess, m.shininess),
          scalar(MaterialParam::Ior, m.ior), scalar(MaterialParam::Dissolve, m.dissolve),
          m.illum == -1 ? std::string() : scalar(MaterialParam::Illum, m.illum)})
        if (!why.empty()) return why;
    return "";
}

}  // namespace thicket
