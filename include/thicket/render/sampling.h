#pragma once
/// The random numbers and the direction sampling of the light-transport integrators: a small
/// counter-seeded generator (so a pixel's samples depend on (seed, pixel, sample) alone, never on
/// which thread or tile drew them), orthonormal frames, and the warps from the unit square to
/// cosine-weighted hemispheres, cones, spheres and triangles with their densities.
#include <cmath>
#include <cstdint>

#include "thicket/core/vec3.h"

namespace thicket {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;

/// SplitMix64's finaliser: a bijective 64-bit mix (Steele, Lea & Flood 2014).
constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/// PCG32 (O'Neill 2014, XSH-RR output): 64-bit state, 32-bit outputs.
class Rng {
public:
    /// The stream of sample `sample` of pixel `pixel` under the user's `seed`: the three are
    /// mixed into the state and the increment, so neighbouring pixels and samples get
    /// unrelated streams and the same triple always gives the same numbers.
    static Rng for_sample(uint64_t seed, uint64_t pixel, uint64_t sample) {
        const uint64_t a = mix64(seed + 0x9e3779b97f4a7c15ull);
        const uint64_t b = mix64(a ^ mix64(pixel + 0x632be59bd9b4e019ull));
        const uint64_t c = mix64(b ^ mix64(sample + 0x8cb92ba72f3d8dd7ull));
        return Rng(c, mix64(c ^ 0xd1b54a32d192ed03ull));
    }
    /// A generator on stream `stream` starting from `state`.
    Rng(uint64_t state, uint64_t stream) : inc_((stream << 1u) | 1u) {
        next_u32();
        state_ += state;
        next_u32();
    }
    /// The next 32 random bits.
    uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ull + inc_;
        const auto xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const auto rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    /// A float uniform in [0, 1) with 24 random bits (never 1).
    float uniform() { return float(next_u32() >> 8) * 0x1p-24f; }

private:
    uint64_t state_ = 0;
    uint64_t inc_ = 1;
};

/// A right-handed orthonormal frame (t, b, n) around unit `n` (Duff et al. 2017, branchless).
struct Frame {
    Vec3 t, b, n;
    /// The frame whose third axis is unit vector `n`.
    explicit Frame(Vec3 normal) : n(normal) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float c = n.x * n.y * a;
        t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
        b = {c, sign + n.y * n.y * a, -n.y};
    }
    /// Local coordinates (x, y, z) to world: x t + y b + z n.
    Vec3 to_world(Vec3 v) const { return t * v.x + b * v.y + n * v.z; }
};

/// Cosine-weighted direction about +z (Malley: a uniform disk point lifted); density cos / pi.
inline Vec3 sample_cosine_hemisphere(float u0, float u1) {
    const float r = std::sqrt(u0), phi = 2.0f * kPi * u1;
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.0f, 1.0f - u0))};
}

/// Uniform direction on the unit sphere; density 1 / (4 pi).
inline Vec3 sample_uniform_sphere(float u0, float u1) {
    const float z = 1.0f - 2.0f * u0, r = std::sqrt(std::fmax(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u1;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Uniform direction in the cone about +z whose axis-to-edge angle has cosine cos_max, given
/// one_minus_cos = 1 - cos_max computed without cancellation by the caller; density
/// 1 / (2 pi one_minus_cos).
inline Vec3 sample_uniform_cone(float u0, float u1, float one_minus_cos) {
    const float one_minus_z = u0 * one_minus_cos;
    const float z = 1.0f - one_minus_z;
    const float r = std::sqrt(std::fmax(0.0f, one_minus_z * (2.0f - one_minus_z)));
    const float phi = 2.0f * kPi * u1;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Barycentric weights (b1, b2) of a point uniform on a triangle (square-root warp); the point is
/// v0 + b1 (v1 - v0) + b2 (v2 - v0), density 1 / area.
inline void sample_triangle(float u0, float u1, float& b1, float& b2) {
    const float su = std::sqrt(u0);
    b1 = 1.0f - su;
    b2 = u1 * su;
}

/// Veach's power heuristic (beta = 2) for a sample of density pdf_a against the other
/// strategy's pdf_b: pdf_a^2 / (pdf_a^2 + pdf_b^2); 0 when both are 0; 1 when pdf_b is 0.
inline float power_heuristic(float pdf_a, float pdf_b) {
    // In double: squared in float, two pdfs above ~1.8e19 both became inf, each weight 1, summing to 2.
    const double a = double(pdf_a) * pdf_a, b = double(pdf_b) * pdf_b;
    if (!(a + b > 0.0)) return 0.0f;
    if (std::isinf(a)) return std::isinf(b) ? 0.5f : 1.0f;
    return float(a / (a + b));
}

/// Rec. 709 luminance of a linear RGB colour.
constexpr float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/// The mirror image of `w` (pointing away from the surface) about unit normal `n`.
constexpr Vec3 reflect(Vec3 w, Vec3 n) { return n * (2.0f * dot(w, n)) - w; }

}  // namespace thicket
