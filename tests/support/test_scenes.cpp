#include "support/test_scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>

#include "thicket/prims/control_mesh.h"
#include "thicket/prims/teapot_patches.h"

namespace thicket::testing {

namespace {

void add_triangle(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c) {
    const auto base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

Scene make(std::string name, TriangleMesh mesh) {
    Scene s;
    s.name = std::move(name);
    s.mesh = std::move(mesh);
    return s;
}

Vec3 random_point(std::mt19937& rng, Vec3 lo, Vec3 hi) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return {lo.x + (hi.x - lo.x) * u(rng), lo.y + (hi.y - lo.y) * u(rng), lo.z + (hi.z - lo.z) * u(rng)};
}

TriangleMesh random_soup(size_t count, Vec3 lo, Vec3 hi, float size, uint32_t seed) {
    std::mt19937 rng(seed);
    TriangleMesh m;
    for (size_t i = 0; i < count; ++i) {
        const Vec3 c = random_point(rng, lo, hi);
        add_triangle(m, c + random_point(rng, Vec3(-size), Vec3(size)), c + random_point(rng, Vec3(-size), Vec3(size)),
                     c + random_point(rng, Vec3(-size), Vec3(size)));
    }
    return m;
}

/// A closed, subdivided cube: every edge is shared by exactly two triangles.
TriangleMesh closed_cube(int n) {
    TriangleMesh m;
    auto vertex = [&](Vec3 p) {
        for (uint32_t i = 0; i < m.positions.size(); ++i)
            if (m.positions[i] == p) return i;
        m.positions.push_back(p);
        return uint32_t(m.positions.size() - 1);
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    auto corner = [&](int a, int b) {
                        Vec3 p;
                        p[axis] = float(side);
                        p[(axis + 1) % 3] = float(a) / float(n);
                        p[(axis + 2) % 3] = float(b) / float(n);
                        return vertex(p);
                    };
                    const uint32_t v00 = corner(i, j), v10 = corner(i + 1, j), v11 = corner(i + 1, j + 1),
                                   v01 = corner(i, j + 1);
                    m.indices.insert(m.indices.end(), {v00, v10, v11, v00, v11, v01});
                }
    return m;
}

TriangleMesh translated(TriangleMesh m, Vec3 by, float scale) {
    for (Vec3& p : m.positions) p = p * scale + by;
    return m;
}

/// Where the ray first meets shape s (any t >= ray.tmin), if it does.
std::optional<float> shape_hit(const Shape& s, const Ray& ray) {
    ShapeHit h;
    const bool hit = std::visit([&](const auto& k) { return k.intersect(ray, kInfinity, h); }, s);
    return hit ? std::optional<float>(h.t) : std::nullopt;
}

/// Rays for scenes with shapes, `share` of each kind (see conformance_rays()).
void add_shape_rays(const Scene& scene, size_t share, std::mt19937& rng, std::vector<Ray>& rays) {
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const size_t n = scene.shapes.size();
    auto near_origin = [&](const Aabb& b) {
        const Vec3 e = max(b.extent(), Vec3(1e-30f));
        return random_point(rng, b.min - e * 1.5f, b.max + e * 1.5f);
    };
    // Aimed at a point of the shape's box from near it (the scene may be dominated by a huge shape).
    for (size_t i = 0; i < share; ++i) {
        const Aabb b = shape_bounds(scene.shapes[rng() % n]);
        const Vec3 o = near_origin(b);
        rays.push_back({o, 0.0f, random_point(rng, b.min, b.max) - o, kInfinity});
    }
    // Grazing the silhouette: bisect the aim point between a hit and a miss beside the box.
    for (size_t i = 0; i < share; ++i) {
        const Shape& s = scene.shapes[rng() % n];
        const Aabb b = shape_bounds(s);
        const Vec3 o = near_origin(b);
        Vec3 in = b.center(), out = b.center() + (random_point(rng, Vec3(-1), Vec3(1))) * (2.0f * length(b.extent()));
        for (int k = 0; k < 8 && !shape_hit(s, {o, 0.0f, in - o, kInfinity}); ++k) in = random_point(rng, b.min, b.max);
        for (int k = 0; k < 40; ++k) {
            const Vec3 mid = (in + out) * 0.5f;
            (shape_hit(s, {o, 0.0f, mid - o, kInfinity}) ? in : out) = mid;
        }
        rays.push_back({o, 0.0f, ((i % 2) ? in : out) - o, kInfinity});
    }
    // A ray from near a random shape aimed into its box, scaled so that its hit (if any) is at t = 1.
    auto aimed = [&]() -> std::pair<Ray, bool> {
        const Shape& s = scene.shapes[rng() % n];
        const Aabb b = shape_bounds(s);
        const Vec3 o = near_origin(b);
        const Ray probe{o, 0.0f, random_point(rng, b.min, b.max) - o, kInfinity};
        const auto t = shape_hit(s, probe);
        return {{o, 0.0f, probe.dir * (t ? *t : 1.0f), kInfinity}, t.has_value()};
    };
    // Starting on a shape (tmin 0, where the origin's own surface may be hit at t ~ 0), any direction.
    for (size_t i = 0; i < share; ++i) {
        const auto [probe, hit] = aimed();
        Vec3 d = random_point(rng, Vec3(-1), Vec3(1));
        if (dot(d, d) == 0.0f) d = {0, 1, 0};
        rays.push_back({hit ? probe.org + probe.dir : probe.org, 0.0f, d, kInfinity});
    }
    // Narrow and shifted windows around a shape's hit at t = 1.
    for (size_t i = 0; i < share; ++i) {
        const Ray probe = aimed().first;
        const Vec3 o = probe.org, d = probe.dir;
        switch (i % 4) {
        case 0: rays.push_back({o, 0.999f, d, 1.001f}); break;
        case 1: rays.push_back({o, 1.0001f, d, kInfinity}); break;  // just beyond: the far root
        case 2: rays.push_back({o, 0.0f, d, 0.9999f}); break;       // stops short of it
        default: rays.push_back({o, 1.0f, d, 1.0f}); break;         // a single point
        }
    }
}

/// A Bezier patch moved by `by` after scaling by `scale` (exact: patches are affinely invariant).
BezierPatch placed(const BezierPatch& p, Vec3 by, float scale) {
    BezierPatch::ControlPoints cp = p.control_points();
    for (Vec3& c : cp) c = by + c * scale;
    return BezierPatch(cp);
}

/// The complex kernels (Bezier patches, a subdivision surface, implicit surfaces by both methods,
/// blobs, both fractals), placed among the spheres, tori and triangles so that boxes overlap.
void add_complex_shapes(Scene& s) {
    for (const BezierPatch& p : teapot_patches()) s.add_shape(placed(p, {-0.3f, -0.5f, -0.9f}, 0.12f));  // on the floor
    {
        ControlMesh cage = cube_control_mesh();
        for (Vec3& p : cage.positions) p = Vec3{0.8f, -0.3f, 0.8f} + p * 0.2f;
        s.add_shape(SubdivisionSurface(cage, 2));
    }
    auto placement = [](Vec3 center, float scale, ImplicitMethod method) {
        ImplicitOptions o;
        o.center = center;
        o.scale = scale;
        o.method = method;
        return o;
    };
    s.add_shape(Implicit("tangle-cube", placement({-0.9f, 0.1f, -0.2f}, 0.12f, ImplicitMethod::interval)));
    s.add_shape(Implicit("barth-sextic", placement({0.2f, 0.8f, -0.7f}, 0.25f, ImplicitMethod::interval), 1.0));
    s.add_shape(Implicit("tangle-cube", placement({0.9f, 0.9f, 0.9f}, 0.1f, ImplicitMethod::sphere_tracing)));
    s.add_shape(Blobs(BlobSum{{Blob{{0, 0, 0}, 0.5, 1}, Blob{{0.6, 0.2, 0}, 0.4, 1}, Blob{{0.2, 0.6, 0.3}, 0.45, 0.8}}, 0.3},
                      placement({-0.3f, 0.3f, 0.9f}, 0.5f, ImplicitMethod::interval)));
    Julia::Params julia;
    julia.march.center = {0.8f, 0.6f, 0.2f};
    julia.march.scale = 0.25f;
    julia.march.iterations = 8;
    s.add_shape(Julia(julia));
    Mandelbulb::Params bulb;
    bulb.march.center = {-0.8f, -0.1f, -0.7f};
    bulb.march.scale = 0.25f;
    bulb.march.iterations = 6;
    s.add_shape(Mandelbulb(bulb));
}

}  // namespace

Scene mixed_scene() {
    Scene s;
    s.name = "mixed";
    s.add_mesh(random_soup(150, {-1, -1, -1}, {1, 1, 1}, 0.15f, 31));
    s.add_shape(Sphere{{0, 0, 0}, 0.5f});
    s.add_shape(Sphere{{1, 0, 0}, 0.5f});                           // touches the first at (0.5, 0, 0)
    s.add_shape(Torus{{0.2f, 0.1f, -0.1f}, {0, 1, 0}, 0.7f, 0.15f});  // cuts through the first sphere
    {
        TriangleMesh floor;  // the first sphere rests on it at (0, -0.5, 0)
        add_triangle(floor, {-1.5f, -0.5f, -1.5f}, {1.5f, -0.5f, -1.5f}, {1.5f, -0.5f, 1.5f});
        add_triangle(floor, {-1.5f, -0.5f, -1.5f}, {1.5f, -0.5f, 1.5f}, {-1.5f, -0.5f, 1.5f});
        s.add_mesh(floor);
    }
    s.add_shape(Sphere{{1, 0, 0}, 0.5f});  // the same sphere again: coincident surfaces tie
    const Vec3 tilted = normalize(Vec3{1, 1, 0});
    s.add_shape(Torus{{-0.6f, 0.6f, 0.5f}, tilted, 0.35f, 0.1f});
    s.add_shape(Sphere{{-0.6f, 0.6f, 0.5f}, 0.2f});  // in that torus's hole, 0.05 from the tube
    s.add_mesh(translated(closed_cube(3), {-1.2f, -0.2f, 0.6f}, 0.4f));
    s.add_shape(Torus{{0.3f, -0.7f, 0.4f}, {0, 0, 1}, 2e-4f, 5e-5f});  // tiny
    s.add_shape(Sphere{{0.3f, -0.7f, 0.4f}, 1e-4f});                 // tiny, in its hole
    s.add_shape(Torus{{0.5f, 0.5f, -0.5f}, normalize(Vec3{0.3f, -0.2f, 0.9f}), 0.3f, 0.02f});  // thin
    s.add_shape(Sphere{{0, -1e4f - 1.2f, 0}, 1e4f});  // huge: most ray origins lie inside it
    add_complex_shapes(s);
    return s;
}

std::vector<Scene> nasty_scenes() {
    std::vector<Scene> scenes;
    scenes.push_back(make("empty", {}));
    {
        TriangleMesh m;
        add_triangle(m, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
        scenes.push_back(make("one-triangle", std::move(m)));
    }
    {
        TriangleMesh m = random_soup(300, {0, 0, 0}, {1, 1, 1}, 0.05f, 7);
        std::mt19937 rng(11);
        for (int i = 0; i < 100; ++i) {
            const Vec3 p = random_point(rng, {0, 0, 0}, {1, 1, 1});
            const Vec3 q = random_point(rng, {0, 0, 0}, {1, 1, 1});
            add_triangle(m, p, p, p);                        // a point
            add_triangle(m, p, q, p + (q - p) * 0.5f);       // collinear
            add_triangle(m, p, p, q);                        // repeated vertex
        }
        scenes.push_back(make("zero-area", std::move(m)));
    }
    {
        TriangleMesh m;
        for (int copy = 0; copy < 8; ++copy) {
            add_triangle(m, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
            add_triangle(m, {0, 1, 0}, {1, 0, 0}, {0, 0, 0});  // reversed winding
            add_triangle(m, {0.2f, 0.2f, 0.5f}, {0.9f, 0.3f, 0.5f}, {0.4f, 0.8f, 0.5f});
        }
        scenes.push_back(make("duplicates", std::move(m)));
    }
    {
        // Many overlapping triangles in one plane, and an axis-aligned tessellated floor.
        TriangleMesh m;
        std::mt19937 rng(5);
        for (int i = 0; i < 200; ++i) {
            const Vec3 a = random_point(rng, {0, 0, 0}, {1, 1, 0}), b = random_point(rng, {0, 0, 0}, {1, 1, 0}),
                       c = random_point(rng, {0, 0, 0}, {1, 1, 0});
            add_triangle(m, a, b, c);
        }
        for (int i = 0; i < 10; ++i)
            for (int j = 0; j < 10; ++j) {
                const Vec3 p(float(i) * 0.1f, 0.5f, float(j) * 0.1f);
                add_triangle(m, p, p + Vec3(0.1f, 0, 0), p + Vec3(0.1f, 0, 0.1f));
                add_triangle(m, p, p + Vec3(0.1f, 0, 0.1f), p + Vec3(0, 0, 0.1f));
            }
        scenes.push_back(make("coplanar", std::move(m)));
    }
    {
        // Triangles of many sizes and orientations, all with the same centroid.
        TriangleMesh m;
        std::mt19937 rng(3);
        const Vec3 c(1, 2, 3);
        for (int i = 0; i < 300; ++i) {
            const Vec3 a = random_point(rng, Vec3(-1), Vec3(1)) * float(1 + i % 7);
            const Vec3 b = random_point(rng, Vec3(-1), Vec3(1)) * float(1 + i % 5);
            add_triangle(m, c + a, c + b, c - a - b);
        }
        scenes.push_back(make("same-centroid", std::move(m)));
    }
    scenes.push_back(make("huge", random_soup(500, Vec3(1e7f), Vec3(1.5e7f), 2e5f, 21)));
    scenes.push_back(make("tiny", random_soup(500, Vec3(-1e-7f), Vec3(1e-7f), 2e-8f, 22)));
    scenes.push_back(make("closed-cube", closed_cube(6)));
    {
        // Long thin sticks (triangular prisms) across the box's diagonals, many of them parallel:
        // every stick's axis-aligned box is nearly the whole scene, its oriented box a sliver.
        TriangleMesh m;
        std::mt19937 rng(17);
        const Vec3 diagonals[4] = {{1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
        for (int i = 0; i < 120; ++i) {
            const Vec3 d = normalize(diagonals[i % 4] + random_point(rng, Vec3(-0.02f), Vec3(0.02f)));
            const Vec3 c = random_point(rng, Vec3(-0.3f), Vec3(0.3f));
            const Vec3 a = c - d * 0.8f, b = c + d * 0.8f;
            // A random ring orientation: with a world axis here, one face of every stick would be
            // exactly parallel to the axis-parallel rays, whose triangle tests then report
            // ill-conditioned hits anywhere in the triangle's box (see docs/obb.md).
            const Vec3 u = normalize(cross(d, normalize(random_point(rng, Vec3(-1), Vec3(1)) + Vec3(0.01f, 0, 0))));
            const Vec3 w = cross(d, u);
            const float r = 0.004f;
            const Vec3 ring[3] = {u * r, (w * 0.866f - u * 0.5f) * r, (w * -0.866f - u * 0.5f) * r};
            for (int k = 0; k < 3; ++k) {
                const Vec3 p = ring[k], q = ring[(k + 1) % 3];
                add_triangle(m, a + p, b + p, b + q);
                add_triangle(m, a + p, b + q, a + q);
            }
        }
        scenes.push_back(make("thin-diagonal", std::move(m)));
    }
    scenes.push_back(mixed_scene());
    scenes.push_back(make("soup", random_soup(2000, {-1, -1, -1}, {1, 1, 1}, 0.1f, 23)));
    return scenes;
}

Vec3 random_unit_vector(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    while (true) {
        const Vec3 v{n(rng), n(rng), n(rng)};
        if (length(v) > 1e-3f) return normalize(v);
    }
}

namespace {

/// The configured directory, or THICKET_SHARED_SCENES from the environment when set (so a test can
/// show what a checkout without ../shared does).
std::string configured_shared_dir() {
    const char* env = std::getenv("THICKET_SHARED_SCENES");
    return env ? env : THICKET_SHARED_SCENES;
}

}  // namespace

std::string shared_scene_dir() {
    std::error_code ec;
    const std::string dir = configured_shared_dir();
    return std::filesystem::is_directory(dir, ec) ? dir : "";
}

std::vector<std::string> shared_scene_files() {
    std::vector<std::string> files;
    const std::string dir = shared_scene_dir();
    if (dir.empty()) return files;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".ply" || ext == ".obj") files.push_back(e.path().string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::string shared_scenes_missing_message() {
    return std::string("shared scenes not found at ") + configured_shared_dir() +
           " (expected ../shared/scenes beside the checkout); real-scene tests skipped";
}

const Scene& cached_scene(const std::string& path) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<Scene>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = cache[path];
    if (!slot) slot = std::make_unique<Scene>(load_scene(path));
    return *slot;
}

std::vector<Ray> conformance_rays(const Scene& scene, size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    std::vector<Ray> rays;
    Aabb b = scene.bounds();
    if (b.empty()) b = Aabb{Vec3(-1), Vec3(1)};
    const Vec3 ext = max(b.extent(), Vec3(max_component(b.extent()) * 0.01f + 1e-30f));
    const Vec3 lo = b.min - ext * 0.25f, hi = b.max + ext * 0.25f;
    const size_t tris = scene.mesh.triangle_count();
    auto random_dir = [&] {
        while (true) {
            const Vec3 d = random_point(rng, Vec3(-1), Vec3(1));
            const float l2 = dot(d, d);
            if (l2 > 1e-4f && l2 <= 1.0f) return d;
        }
    };
    auto surface_point = [&](uint32_t t, float a, float c) {
        const Vec3 v0 = scene.mesh.vertex(t, 0), v1 = scene.mesh.vertex(t, 1), v2 = scene.mesh.vertex(t, 2);
        return v0 + (v1 - v0) * a + (v2 - v0) * c;
    };
    // Six kinds of rays for triangles, four more for shapes; the rest fully random.
    const size_t share = std::max<size_t>(1, count / (scene.has_shapes() ? 10 : 6));

    // Random origins around the scene, aimed at random points inside it or in random directions.
    for (size_t i = 0; i < share; ++i) {
        const Vec3 o = random_point(rng, lo, hi);
        const Vec3 d = (i % 2) ? random_point(rng, b.min, b.max) - o : random_dir();
        rays.push_back({o, 0.0f, d, kInfinity});
    }
    // Aimed exactly at vertices and edge midpoints: shared edges and vertices of closed meshes.
    // In turn each of the three vertices, then each of the three edges (v0v1, v1v2, v2v0).
    for (size_t i = 0; tris && i < share; ++i) {
        const auto t = uint32_t(rng() % tris);
        const int k = int(i % 6), corner = k % 3;
        const Vec3 target = k < 3 ? scene.mesh.vertex(t, corner)
                                  : (scene.mesh.vertex(t, corner) + scene.mesh.vertex(t, (corner + 1) % 3)) * 0.5f;
        const Vec3 o = random_point(rng, lo, hi);
        rays.push_back({o, 0.0f, target - o, kInfinity});
    }
    // Axis-parallel, with +0 and -0 in the other components; origins on vertex coordinates too.
    for (size_t i = 0; i < share; ++i) {
        const int axis = int(i % 3);
        const float sign = (i / 3) % 2 ? -1.0f : 1.0f;
        Vec3 d((i / 6) % 2 ? -0.0f : 0.0f);
        d[axis] = sign;
        Vec3 o = random_point(rng, lo, hi);
        if (tris && i % 2 == 0) {
            const Vec3 v = scene.mesh.vertex(rng() % tris, int(rng() % 3));
            o = v;  // passes exactly through a vertex (or along an edge of an axis-aligned mesh)
        }
        o[axis] = sign > 0 ? lo[axis] : hi[axis];
        rays.push_back({o, 0.0f, d, kInfinity});
    }
    // Starting on a surface (tmin 0): the origin's own triangle may be hit at t = 0.
    for (size_t i = 0; tris && i < share; ++i) {
        const auto t = uint32_t(rng() % tris);
        const float a = u01(rng), c = u01(rng) * (1.0f - a);
        rays.push_back({surface_point(t, a, c), 0.0f, random_dir(), kInfinity});
    }
    // Narrow and shifted windows around a hit point along a random ray.
    for (size_t i = 0; tris && i < share; ++i) {
        const auto t = uint32_t(rng() % tris);
        const Vec3 target = surface_point(t, 0.3f, 0.3f);
        const Vec3 o = random_point(rng, lo, hi);
        const Vec3 d = target - o;  // the target lies at t = 1
        switch (i % 4) {
        case 0: rays.push_back({o, 0.999f, d, 1.001f}); break;
        case 1: rays.push_back({o, 1.001f, d, kInfinity}); break;  // beyond the target
        case 2: rays.push_back({o, 0.0f, d, 0.999f}); break;       // stops short of it
        default: rays.push_back({o, 1.0f, d, 1.0f}); break;        // a single point
        }
    }
    if (scene.has_shapes()) add_shape_rays(scene, share, rng, rays);
    // The rest: fully random.
    while (rays.size() < count) rays.push_back({random_point(rng, lo, hi), 0.0f, random_dir(), kInfinity});
    return rays;
}

}  // namespace thicket::testing
