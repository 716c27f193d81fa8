#pragma once
/// Where a triangle stops having an interior for rays (Triangles::degenerate): the sine of the
/// angle between its edges, |e1 x e2| / (|e1| |e2|), at or below kDegenerateSine. Constants only,
/// so that the bvh8 kernels (compiled per ISA, bvh8/node.h) share them with baseline code.

namespace thicket {

/// Float triangles (1e-6) and its square, in double as the test compares it.
inline constexpr float kDegenerateSineFloat = 1e-6f;
inline constexpr double kDegenerateSine2Float = double(kDegenerateSineFloat) * double(kDegenerateSineFloat);
/// Double triangles (precision=double).
inline constexpr double kDegenerateSineDouble = 1e-12;
inline constexpr double kDegenerateSine2Double = 1e-24;

}  // namespace thicket
