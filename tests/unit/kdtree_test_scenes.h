#pragma once
// Scenes shared by the kD-tree tests (kdtree_test.cpp, kdtree_traversal_test.cpp).
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "thicket/scene/scene.h"

namespace thicket::kdtest {

inline void add_triangle(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c) {
    const auto base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

inline Scene make_scene(std::string name, TriangleMesh mesh) {
    Scene s;
    s.name = std::move(name);
    s.mesh = std::move(mesh);
    return s;
}

/// Random triangles of mixed sizes; a third lie in axis-aligned planes on a coarse lattice of
/// positions (planar events, primitives in split planes, coplanar overlaps), a few repeat.
inline Scene mixed_scene(uint32_t seed, size_t count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    TriangleMesh m;
    auto point = [&] { return Vec3(u(rng), u(rng), u(rng)) * 4.0f - Vec3(2.0f); };
    for (size_t i = 0; i < count; ++i) {
        const float size = i % 5 == 0 ? 1.0f : 0.15f;
        const Vec3 c = point();
        Vec3 a = c + (point() * 0.5f) * size, b = c + (point() * 0.5f) * size, d = c + (point() * 0.5f) * size;
        if (i % 3 == 0) {
            const int axis = int(i % 9) / 3;
            const float plane = std::round(c[axis] * 4.0f) / 4.0f;  // shared planes: coplanar groups
            a[axis] = b[axis] = d[axis] = plane;
        }
        add_triangle(m, a, b, d);
        if (i % 50 == 7) add_triangle(m, a, b, d);  // an exact duplicate
    }
    return make_scene("mixed-" + std::to_string(seed), std::move(m));
}

/// `count` triangles of `scene` drawn at random (fixed seed), in their original order.
inline Scene subsample(const Scene& scene, size_t count, uint32_t seed) {
    std::vector<uint32_t> ids(scene.primitive_count());
    for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
    std::mt19937 rng(seed);
    std::shuffle(ids.begin(), ids.end(), rng);
    ids.resize(std::min(count, ids.size()));
    std::sort(ids.begin(), ids.end());
    TriangleMesh m;
    for (uint32_t t : ids) add_triangle(m, scene.mesh.vertex(t, 0), scene.mesh.vertex(t, 1), scene.mesh.vertex(t, 2));
    return make_scene(scene.name + " (" + std::to_string(ids.size()) + " triangles)", std::move(m));
}

}  // namespace thicket::kdtest
