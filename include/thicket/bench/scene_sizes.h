#pragma once
/// Scenes of a chosen size made from a real one, for measuring how build time grows with N.
///
/// The rule (`thicket compare` documents it): a scene of n triangles made from a scene of m is
/// - for n <= m: n of its triangles chosen uniformly at random without replacement (Knuth's
///   selection sampling, PCG32 seeded with kGrowthSeed), kept in file order;
/// - for n > m: every triangle split r times into four by its edge midpoints (corners first, the
///   middle triangle last, each keeping the winding), with the smallest r such that m * 4^r >= n;
///   then n of those m * 4^r triangles chosen the same way. Only the chosen ones are made.
/// So every size keeps the scene's spatial distribution of geometry, and the same scene, size and
/// seed always give the same triangles. The result is a triangle soup (three vertices of its own
/// per triangle, no materials).
#include <cstddef>
#include <cstdint>

#include "thicket/scene/scene.h"

namespace thicket {

inline constexpr uint64_t kGrowthSeed = 0x7468696b67726f77ULL;  // "thikgrow"
/// Largest size scene_of_size() makes (about 1.7 GB of soup): a guard against typos.
inline constexpr size_t kMaxSceneSize = 50'000'000;

/// Subdivision rounds the rule uses to make n triangles from m (0 when n <= m). Throws Error for
/// m == 0 < n.
int subdivision_rounds(size_t m, size_t n);

/// A scene of exactly n triangles made from `scene` by the rule above, named "<name> (n triangles)".
/// Throws Error, naming the sizes, when the scene is empty and n > 0, or n > kMaxSceneSize.
Scene scene_of_size(const Scene& scene, size_t n, uint64_t seed = kGrowthSeed);

}  // namespace thicket
