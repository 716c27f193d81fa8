#include "thicket/render/bsdf.h"

#include <algorithm>
#include <cmath>

#include "thicket/render/sampling.h"

namespace thicket {

namespace {

Vec3 clamp01(Vec3 c) {
    auto f = [](float x) { return std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 0.0f; };
    return {f(c.x), f(c.y), f(c.z)};
}

bool nonzero(Vec3 c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }

/// Probability of sampling the glossy lobe rather than the diffuse one.
float specular_share(const SurfaceMaterial& m) {
    const float d = luminance(m.albedo), s = luminance(m.specular);
    return d + s > 0.0f ? s / (d + s) : 0.0f;
}

/// The normalised Phong lobe (e + 2) / (2 pi) cos^e(alpha) and its sampling density (e + 1) / (2 pi) cos^e(alpha).
float phong_cos_pow(const SurfaceMaterial& m, Vec3 r, Vec3 wi) {
    const float c = dot(r, wi);
    return c > 0.0f ? std::pow(c, m.exponent) : 0.0f;
}

}  // namespace

bool SurfaceMaterial::scatters() const {
    switch (kind) {
        case SurfaceKind::Lambert: return nonzero(albedo);
        case SurfaceKind::Mirror: return nonzero(specular);
        case SurfaceKind::Glossy: return nonzero(albedo) || nonzero(specular);
        case SurfaceKind::Dielectric: return true;
    }
    return false;
}

SurfaceMaterial lambert(Vec3 albedo, Vec3 emission) {
    SurfaceMaterial m;
    m.kind = SurfaceKind::Lambert;
    m.albedo = clamp01(albedo);
    m.emission = emission;
    return m;
}

SurfaceMaterial mirror(Vec3 tint) {
    SurfaceMaterial m;
    m.kind = SurfaceKind::Mirror;
    m.specular = clamp01(tint);
    return m;
}

SurfaceMaterial glossy(Vec3 albedo, Vec3 specular, float exponent) {
    SurfaceMaterial m;
    m.kind = SurfaceKind::Glossy;
    m.albedo = clamp01(albedo);
    m.specular = clamp01(specular);
    for (int i = 0; i < 3; ++i) {
        const float sum = m.albedo[i] + m.specular[i];
        if (sum > 1.0f) {
            m.albedo[i] /= sum;
            m.specular[i] /= sum;
        }
    }
    m.exponent = std::isfinite(exponent) ? std::max(exponent, 0.0f) : 0.0f;
    return m;
}

SurfaceMaterial dielectric(float ior) {
    SurfaceMaterial m;
    m.kind = SurfaceKind::Dielectric;
    m.ior = std::isfinite(ior) && ior > 0.0f ? ior : 1.5f;
    return m;
}

SurfaceMaterial surface_from_material(const Material& mtl) {
    SurfaceMaterial m;
    const bool transparent = mtl.dissolve < 1.0f || mtl.illum == 4 || mtl.illum == 6 || mtl.illum == 7;
    if (transparent && mtl.ior != 1.0f) {
        m = dielectric(mtl.ior);
    } else if (nonzero(mtl.specular) && (mtl.illum == 3 || mtl.illum == 5 || mtl.shininess >= 1000.0f)) {
        m = mirror(mtl.specular);
    } else if (nonzero(mtl.specular)) {
        m = glossy(mtl.diffuse, mtl.specular, mtl.shininess);
    } else {
        m = lambert(mtl.diffuse);
    }
    m.emission = mtl.emission;
    m.name = mtl.name;
    return m;
}

float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
    const float cos_t = std::sqrt(1.0f - sin2_t);
    const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5f * (rs * rs + rp * rp);
}

float fresnel_transmittance(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f || cos_i == 0.0f) return 0.0f;
    const float cos_t = std::sqrt(1.0f - sin2_t);
    const float ts = 2.0f * cos_i / (cos_i + eta * cos_t);
    const float tp = 2.0f * cos_i / (eta * cos_i + cos_t);
    return (eta * cos_t / cos_i) * 0.5f * (ts * ts + tp * tp);
}

bool sample_bsdf(const SurfaceMaterial& m, Vec3 n, Vec3 wo, float u0, float u1, float u2, BsdfSample& out) {
    const float cos_o = dot(n, wo);
    if (m.kind == SurfaceKind::Dielectric) {
        const bool entering = cos_o > 0.0f;
        const Vec3 nf = entering ? n : -n;  // normal on wo's side
        const float eta = entering ? m.ior : 1.0f / m.ior;  // n_t / n_i
        const float cos_i = std::fabs(cos_o);
        const float r = fresnel_dielectric(cos_i, eta);
        if (u0 < r) {
            out.wi = reflect(wo, nf);
            out.weight = Vec3{1.0f};
            out.pdf = r;
        } else {
            const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
            const float cos_t = std::sqrt(std::fmax(0.0f, 1.0f - sin2_t));
            out.wi = normalize(-wo / eta + nf * (cos_i / eta - cos_t));
            // Radiance is compressed by (n_i / n_t)^2 on entering a denser medium (and expanded
            // on leaving it), so a lossless interface carries 1 / eta^2 of it across.
            out.weight = Vec3{1.0f / (eta * eta)};
            out.pdf = 1.0f - r;
        }
        out.delta = true;
        return true;
    }
    const Vec3 nf = cos_o >= 0.0f ? n : -n;  // opaque surfaces reflect on both sides
    if (m.kind == SurfaceKind::Mirror) {
        out.wi = reflect(wo, nf);
        out.weight = m.specular;
        out.pdf = 1.0f;
        out.delta = true;
        return nonzero(m.specular);
    }
    out.delta = false;
    if (m.kind == SurfaceKind::Glossy && u2 < specular_share(m)) {
        const Vec3 r = reflect(wo, nf);
        const float cos_a = std::pow(u0, 1.0f / (m.exponent + 1.0f));
        const float sin_a = std::sqrt(std::fmax(0.0f, 1.0f - cos_a * cos_a));
        const float phi = 2.0f * kPi * u1;
        out.wi = normalize(Frame(r).to_world({sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a}));
    } else {
        out.wi = normalize(Frame(nf).to_world(sample_cosine_hemisphere(u0, u1)));
    }
    if (!(dot(out.wi, nf) > 0.0f)) return false;
    out.pdf = pdf_bsdf(m, n, wo, out.wi);
    if (!(out.pdf > 0.0f)) return false;
    out.weight = eval_bsdf(m, n, wo, out.wi) / out.pdf;
    return nonzero(out.weight);
}

Vec3 eval_bsdf(const SurfaceMaterial& m, Vec3 n, Vec3 wo, Vec3 wi) {
    if (m.delta()) return {};
    const float cos_o = dot(n, wo), cos_i = dot(n, wi);
    if (!(cos_o * cos_i > 0.0f)) return {};  // opposite sides: opaque surfaces transmit nothing
    const float c = std::fabs(cos_i);
    Vec3 f = m.albedo * kInvPi;
    if (m.kind == SurfaceKind::Glossy) {
        const Vec3 r = reflect(wo, cos_o > 0.0f ? n : -n);
        f += m.specular * ((m.exponent + 2.0f) * (0.5f * kInvPi) * phong_cos_pow(m, r, wi));
    }
    return f * c;
}

float pdf_bsdf(const SurfaceMaterial& m, Vec3 n, Vec3 wo, Vec3 wi) {
    if (m.delta()) return 0.0f;
    const float cos_o = dot(n, wo), cos_i = dot(n, wi);
    if (!(cos_o * cos_i > 0.0f)) return 0.0f;
    const float diffuse = std::fabs(cos_i) * kInvPi;
    if (m.kind != SurfaceKind::Glossy) return diffuse;
    const float s = specular_share(m);
    const Vec3 r = reflect(wo, cos_o > 0.0f ? n : -n);
    const float lobe = (m.exponent + 1.0f) * (0.5f * kInvPi) * phong_cos_pow(m, r, wi);
    return (1.0f - s) * diffuse + s * lobe;
}

}  // namespace thicket
