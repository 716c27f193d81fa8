#include "thicket/bench/scene_sizes.h"

#include <string>

#include "thicket/bench/rng.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

struct Tri {
    Vec3 a, b, c;
};

// Child `d` of the midpoint subdivision: 0, 1, 2 at corners a, b, c, 3 the middle; all keep the
// parent's winding.
Tri child(const Tri& t, unsigned d) {
    const Vec3 ab = (t.a + t.b) * 0.5f, bc = (t.b + t.c) * 0.5f, ca = (t.c + t.a) * 0.5f;
    switch (d) {
    case 0: return {t.a, ab, ca};
    case 1: return {ab, t.b, bc};
    case 2: return {ca, bc, t.c};
    default: return {ab, bc, ca};
    }
}

}  // namespace

int subdivision_rounds(size_t m, size_t n) {
    if (n <= m) return 0;
    if (m == 0) throw Error("cannot make a scene of " + std::to_string(n) + " triangles from an empty scene");
    int r = 0;
    for (uint64_t have = m; have < n; have *= 4) ++r;
    return r;
}

Scene scene_of_size(const Scene& scene, size_t n, uint64_t seed) {
    if (n > kMaxSceneSize)
        throw Error("scene size " + std::to_string(n) + " is larger than the most this makes (" +
                    std::to_string(kMaxSceneSize) + " triangles)");
    // The sizes are made of the scene's triangles only: its shapes (spheres, patches, ...) cannot
    // be split into four, and counting them here read past the end of the triangles.
    const size_t m = scene.mesh.triangle_count();
    if (m == 0)
        throw Error(scene.name + ": has no triangles (" + std::to_string(scene.shapes.size()) +
                    " shapes): scenes of growing size are made by splitting triangles; measure it with --no-growth");
    const int rounds = subdivision_rounds(m, n);
    const uint64_t per_parent = uint64_t(1) << (2 * rounds);
    const uint64_t pool = uint64_t(m) * per_parent;

    Scene out;
    out.name = scene.name + " (" + std::to_string(n) + " triangles)";
    out.mesh.positions.reserve(3 * n);
    out.mesh.indices.reserve(3 * n);
    // Selection sampling (Knuth, TAOCP vol. 2, algorithm S): take item i with probability
    // needed / remaining. It picks exactly n, in order, in one pass and no extra memory.
    Pcg32 rng(seed);
    uint64_t needed = n;
    for (uint64_t i = 0; i < pool && needed > 0; ++i) {
        const double u = double(rng.next_u32()) * (1.0 / 4294967296.0);
        if (double(pool - i) * u >= double(needed)) continue;
        --needed;
        const size_t parent = size_t(i / per_parent);
        Tri t{scene.mesh.vertex(parent, 0), scene.mesh.vertex(parent, 1), scene.mesh.vertex(parent, 2)};
        // The path from the parent to the chosen descendant: base-4 digits, most significant first.
        const uint64_t path = i % per_parent;
        for (int level = rounds - 1; level >= 0; --level) t = child(t, unsigned(path >> (2 * level)) & 3u);
        const auto base = uint32_t(out.mesh.positions.size());
        out.mesh.positions.insert(out.mesh.positions.end(), {t.a, t.b, t.c});
        out.mesh.indices.insert(out.mesh.indices.end(), {base, base + 1, base + 2});
    }
    return out;
}

}  // namespace thicket
