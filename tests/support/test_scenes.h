#pragma once
// Scenes and ray sets the conformance suite runs every structure on.
#include <random>
#include <string>
#include <vector>

#include "thicket/core/ray.h"
#include "thicket/scene/scene.h"

namespace thicket::testing {

/// Generated scenes that break naive structures: empty, one triangle, zero-area and duplicate
/// triangles, coplanar overlaps, all centroids equal, huge and tiny coordinates, a closed mesh,
/// triangles mixed with shapes (mixed_scene()). The last one is the random soup.
std::vector<Scene> nasty_scenes();

/// Triangles and every shape kernel with interleaved ids: overlapping, touching and coincident
/// spheres and tori, a sphere in a torus's hole, tiny ones (1e-4) and a huge one (radius 1e4) that
/// holds most ray origins inside it; the teapot's 32 Bezier patches, a subdivision surface,
/// implicit surfaces (interval and sphere tracing), blobs, a Julia set and a Mandelbulb.
Scene mixed_scene();

/// A random unit vector (normal distribution, normalized), for tests that shoot from every side.
Vec3 random_unit_vector(std::mt19937& rng);

/// Directory of the shared real scenes, or "" when ../shared/scenes is absent.
std::string shared_scene_dir();
/// Every shared scene file (*.ply, *.obj) path, sorted; empty when absent.
std::vector<std::string> shared_scene_files();
/// Message for GTEST_SKIP when the shared scenes are missing.
std::string shared_scenes_missing_message();

/// Loads a scene once per process (real scenes are large; every test reuses them).
const Scene& cached_scene(const std::string& path);

/// The rays every structure must answer like brute force on `scene`: random, aimed at
/// vertices and edge midpoints, axis-parallel with +-0 components, starting on surfaces, and
/// with narrow [tmin, tmax] windows around and beside the true hit. With shapes, also rays
/// aimed at each shape from near it, grazing its silhouette, starting on it, and windowed around
/// its hits. Deterministic per seed.
std::vector<Ray> conformance_rays(const Scene& scene, size_t count, uint32_t seed = 1);

}  // namespace thicket::testing
