#pragma once
/// The bench's random numbers: a PCG32 generator (O'Neill 2014, XSH-RR output) and samplers built
/// only from +, -, *, / and sqrt. Those operations are correctly rounded under IEEE 754, so the
/// same seed gives bit-identical rays with any standard library (std:: distributions and sin/cos
/// would not).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "thicket/core/vec3.h"

namespace thicket {

class Pcg32 {
public:
    /// A generator on stream `stream` (any value; streams are independent sequences) from `seed`.
    constexpr Pcg32(uint64_t seed, uint64_t stream = 0) : inc_((stream << 1) | 1u) {
        next_u32();
        state_ += seed;
        next_u32();
    }

    /// Next 32 uniformly distributed bits.
    constexpr uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }

    /// Uniform float in [0, 1): the top 24 bits scaled by 2^-24, so every value is exact.
    constexpr float next_float() { return float(next_u32() >> 8) * (1.0f / 16777216.0f); }
    /// Uniform float in [-1, 1).
    constexpr float next_signed() { return 2.0f * next_float() - 1.0f; }

private:
    uint64_t state_ = 0;
    uint64_t inc_;
};

/// Uniformly distributed unit vector: rejection sampling of the unit ball, then normalization.
/// Points too close to the centre are rejected too, so the direction is always well defined.
inline Vec3 sample_unit_sphere(Pcg32& rng) {
    while (true) {
        const Vec3 p{rng.next_signed(), rng.next_signed(), rng.next_signed()};
        const float r2 = dot(p, p);
        if (r2 <= 1.0f && r2 > 1e-6f) return p / std::sqrt(r2);
    }
}

/// Uniformly distributed point of the open unit disk, as (x, y, x*x + y*y).
inline Vec3 sample_unit_disk(Pcg32& rng) {
    while (true) {
        const float x = rng.next_signed(), y = rng.next_signed();
        const float r2 = x * x + y * y;
        if (r2 < 1.0f) return {x, y, r2};
    }
}

/// Two unit vectors t, b with (t, b, n) orthonormal, for a unit n (Duff et al. 2017's branchless
/// construction; only arithmetic and copysign, so it is reproducible too).
inline void orthonormal_basis(Vec3 n, Vec3& t, Vec3& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

/// Cosine-weighted direction in the hemisphere around the unit normal n (Malley's method: a
/// uniform disk point lifted onto the hemisphere). Always strictly on n's side: a direction that
/// rounding leaves at cos <= 0 is drawn again.
inline Vec3 sample_cosine_hemisphere(Pcg32& rng, Vec3 n) {
    Vec3 t, b;
    orthonormal_basis(n, t, b);
    while (true) {
        const Vec3 d = sample_unit_disk(rng);
        const float z = std::sqrt(std::max(0.0f, 1.0f - d.z));
        const Vec3 dir = normalize(t * d.x + b * d.y + n * z);
        if (dot(dir, n) > 0.0f) return dir;
    }
}

}  // namespace thicket
