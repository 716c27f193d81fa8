// Scene loading entry point: built-in names first, then dispatch on the file extension.
#include "thicket/scene/scene.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "thicket/core/error.h"
#include "thicket/prims/teapot_patches.h"
#include "thicket/scene/loaders.h"
#include "thicket/util/input_file.h"

namespace thicket {

namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace

/// FNV-1a 64 over each triangle's nine vertex floats (as bits), in order, then the triangle count;
/// with shapes, then every shape (type and parameters) and the id runs.
uint64_t Scene::fingerprint() const {
    uint64_t h = 0xcbf29ce484222325ull;
    auto mix = [&h](uint64_t value, int bytes) {
        for (int i = 0; i < bytes; ++i) {
            h ^= (value >> (8 * i)) & 0xffu;
            h *= 0x100000001b3ull;
        }
    };
    const size_t n = mesh.triangle_count();
    for (size_t t = 0; t < n; ++t)
        for (int c = 0; c < 3; ++c) {
            const Vec3 v = mesh.vertex(t, c);
            mix(std::bit_cast<uint32_t>(v.x), 4);
            mix(std::bit_cast<uint32_t>(v.y), 4);
            mix(std::bit_cast<uint32_t>(v.z), 4);
        }
    mix(uint64_t(n), 8);
    if (shapes.empty()) return h;  // triangle-only scenes keep their fingerprint
    for (const Shape& s : shapes) h = shape_hash(s, h);
    mix(uint64_t(shapes.size()), 8);
    for (const PrimRun& r : runs) {
        mix(r.first, 4);
        mix(r.count, 4);
        mix(r.shapes ? 1u : 0u, 1);
    }
    return h;
}

Aabb Scene::bounds() const {
    if (!instances.empty()) return instanced_bounds(*this);
    Aabb b = mesh.bounds();
    for (const Shape& s : shapes) b.grow(shape_bounds(s));
    return b;
}

PrimRef Scene::locate(uint32_t prim) const {
    return locate_prim(runs, uint32_t(mesh.triangle_count()), prim);
}

Vec3 Scene::geometric_normal(uint32_t prim) const {
    const PrimRef ref = locate(prim);
    if (ref.shape) return Vec3{};
    const Vec3 a = mesh.vertex(ref.index, 0), b = mesh.vertex(ref.index, 1), c = mesh.vertex(ref.index, 2);
    return cross(b - a, c - a);
}

Vec3 Scene::normal(const Ray& world_ray, const Hit& world_hit) const {
    // With instances, hit.prim is a flattened id: the prototype's normal in its instance's space
    // is found as without them, then carried to the world (instance.h).
    InstancePlace place;
    if (!instances.empty() && !place_instanced_hit(*this, world_ray, world_hit, place)) return Vec3{};
    const Ray& ray = instances.empty() ? world_ray : place.ray;
    const Hit& hit = instances.empty() ? world_hit : place.hit;
    if (hit.prim >= primitive_count()) return Vec3{};
    const PrimRef ref = locate(hit.prim);
    if (ref.shape) return place.to_world(shape_normal(shapes[ref.index], ray.org + ray.dir * hit.t, hit.u, hit.v), false);
    // As float as it always was, so the ray sets and images of triangle scenes keep their bits.
    const Vec3 n = geometric_normal(hit.prim);
    const float len = length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) return Vec3{};  // zero-area triangle: no direction
    return place.to_world(n / len, true);
}

namespace {

/// Appends `count` ids of one kind to the runs, merging with the last run of the same kind.
void push_run(std::vector<PrimRun>& runs, uint32_t first, bool shapes, uint32_t index, uint32_t count) {
    if (count == 0) return;
    if (!runs.empty() && runs.back().shapes == shapes) {
        runs.back().count += count;
        return;
    }
    runs.push_back({first, count, shapes, index});
}

/// The runs an empty `runs` stands for: every triangle, then every shape.
void make_runs_explicit(Scene& s) {
    if (!s.runs.empty()) return;
    const auto tris = uint32_t(s.mesh.triangle_count());
    push_run(s.runs, 0, false, 0, tris);
    push_run(s.runs, tris, true, 0, uint32_t(s.shapes.size()));
}

void check_id_space(const Scene& s, size_t more) {
    if (s.primitive_count() + more >= size_t(kNoPrim))
        throw Error(s.name + ": more than " + std::to_string(kNoPrim - 1) + " primitives");
}

/// Opens a geometry for the `count` ids about to be appended; returns its id. An empty list
/// that stands for one geometry over what is there becomes that geometry first.
uint32_t open_geometry(Scene& s, size_t count) {
    const auto first = uint32_t(s.primitive_count());
    if (s.geometries.empty() && first > 0) s.geometries.push_back({0, first, 0, uint32_t(s.mesh.positions.size())});
    s.geometries.push_back({first, uint32_t(count)});
    return uint32_t(s.geometries.size() - 1);
}

}  // namespace

size_t Scene::geometry_count() const {
    if (!geometries.empty()) return geometries.size();
    return primitive_count() > 0 ? 1 : 0;
}

Geometry Scene::geometry(uint32_t id) const {
    if (geometries.empty()) return {0, uint32_t(primitive_count()), 0, uint32_t(mesh.positions.size())};
    return geometries.at(id);
}

uint32_t Scene::geometry_of(uint32_t prim) const {
    if (prim >= primitive_count()) return kNoPrim;
    if (geometries.empty()) return 0;
    // The last geometry starting at or before prim: empty geometries share their successor's
    // start and come before it, so they are never the answer.
    auto it = std::upper_bound(geometries.begin(), geometries.end(), prim,
                               [](uint32_t p, const Geometry& g) { return p < g.first; });
    return uint32_t(it - geometries.begin()) - 1;
}

uint32_t Scene::add_mesh(const TriangleMesh& m) {
    const size_t tris = m.triangle_count();
    check_id_space(*this, tris);
    make_runs_explicit(*this);
    const uint32_t id = open_geometry(*this, tris);
    const size_t old_tris = mesh.triangle_count();
    const auto base = uint32_t(mesh.positions.size());
    geometries[id].vertex_first = base;
    geometries[id].vertex_count = uint32_t(m.positions.size());
    if (!m.positions_double.empty() || !mesh.positions_double.empty()) {
        // Once any mesh brings double coordinates, the scene keeps one double per position (the
        // float ones widened), so that vertex_double() indexes one array.
        for (size_t i = mesh.positions_double.size(); i < base; ++i) mesh.positions_double.emplace_back(mesh.positions[i]);
        if (m.positions_double.size() == m.positions.size())
            mesh.positions_double.insert(mesh.positions_double.end(), m.positions_double.begin(), m.positions_double.end());
        else
            for (const Vec3& p : m.positions) mesh.positions_double.emplace_back(p);
    }
    mesh.positions.insert(mesh.positions.end(), m.positions.begin(), m.positions.end());
    // Not reserve(size + 3 * tris): an exact reserve per mesh reallocates everything for each of
    // N meshes (O(N^2)); insert's geometric growth keeps adding meshes linear.
    for (size_t i = 0; i < 3 * tris; ++i) mesh.indices.push_back(base + m.indices[i]);

    // Materials: once any mesh has them, every triangle has one (a default for those without).
    const bool theirs = m.material_ids.size() == tris && tris > 0;
    if (theirs || !mesh.material_ids.empty()) {
        auto add_default = [this] {
            Material d;
            d.name = "default";
            mesh.materials.push_back(d);
            return uint32_t(mesh.materials.size() - 1);
        };
        if (mesh.material_ids.empty() && old_tris > 0) mesh.material_ids.assign(old_tris, add_default());
        if (theirs) {
            const auto offset = uint32_t(mesh.materials.size());
            mesh.materials.insert(mesh.materials.end(), m.materials.begin(), m.materials.end());
            for (uint32_t id : m.material_ids) mesh.material_ids.push_back(offset + id);
        } else if (tris > 0) {
            mesh.material_ids.insert(mesh.material_ids.end(), tris, add_default());
        }
    }
    push_run(runs, uint32_t(primitive_count() - tris), false, uint32_t(old_tris), uint32_t(tris));
    return id;
}

void Scene::set_vertices(uint32_t id, std::span<const Vec3> positions) {
    const std::string where = "scene '" + name + "', geometry " + std::to_string(id);
    if (id >= geometry_count())
        throw Error(where + ": no such geometry (the scene has " + std::to_string(geometry_count()) + ")");
    const Geometry g = geometry(id);
    if (g.vertex_count == 0 && !positions.empty())
        throw Error(where + " has no vertices to move (shapes, or no mesh)");
    if (positions.size() != g.vertex_count)
        throw Error(where + ": " + std::to_string(positions.size()) + " vertices given, the geometry has " +
                    std::to_string(g.vertex_count) +
                    " (moving vertices keeps the topology: add a new geometry instead)");
    if (size_t(g.vertex_first) + g.vertex_count > mesh.positions.size())
        throw Error(where + ": its vertex range is past the mesh's " + std::to_string(mesh.positions.size()) +
                    " positions");
    for (size_t i = 0; i < positions.size(); ++i) {
        const Vec3& p = positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error(where + ": vertex " + std::to_string(i) + " is (" + std::to_string(p.x) + ", " +
                        std::to_string(p.y) + ", " + std::to_string(p.z) + "), not finite");
    }
    std::copy(positions.begin(), positions.end(), mesh.positions.begin() + g.vertex_first);
    // The moved vertices are float: their double coordinates become the float ones widened.
    if (mesh.positions_double.size() == mesh.positions.size())
        for (size_t i = 0; i < positions.size(); ++i) mesh.positions_double[g.vertex_first + i] = Vec3d(positions[i]);
}

uint32_t Scene::add_shape(const Shape& s) { return add_shapes({&s, 1}); }

uint32_t Scene::add_shapes(std::span<const Shape> added) {
    check_id_space(*this, added.size());
    make_runs_explicit(*this);
    const uint32_t id = open_geometry(*this, added.size());
    const auto first = uint32_t(primitive_count());
    shapes.insert(shapes.end(), added.begin(), added.end());
    push_run(runs, first, true, uint32_t(shapes.size() - added.size()), uint32_t(added.size()));
    return id;
}

TriangleMesh load_mesh(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".ply") return load_ply(path);
    if (ext == ".obj") return load_obj(path);
    if (ext == ".gltf" || ext == ".glb") return load_gltf(path);
    throw Error(path + ": unknown mesh format " + (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                " (supported: .ply, .obj, .gltf, .glb)");
}

const char* builtin_scene_names() { return "cornell, teapot-patches"; }

Scene load_scene(const std::string& path_or_builtin) { return load_scene(path_or_builtin, LoadOptions{}); }

Scene load_scene(const std::string& path_or_builtin, const LoadOptions& options) {
    Scene scene;
    scene.name = path_or_builtin;
    if (path_or_builtin == "cornell") {
        scene.mesh = builtin_cornell_box();
        return scene;
    }
    if (path_or_builtin == "teapot-patches") {
        const std::vector<BezierPatch> patches = teapot_patches();
        scene.add_shapes(std::vector<Shape>(patches.begin(), patches.end()));  // one geometry: the teapot
        return scene;
    }
    const std::string& path = path_or_builtin;
    check_regular_input(path, "scene file");  // no such file, a directory, /dev/zero, a FIFO

    const std::string ext = lower_extension(path);
    if (ext == ".json") {
        scene = load_json_scene(path);
        scene.name = path;
    } else if (ext == ".gltf" || ext == ".glb") {
        scene = load_gltf_scene(path, options);
    } else if (ext == ".ply" || ext == ".obj") {
        scene.mesh = load_mesh(path);
    } else {
        throw Error(path + ": unknown scene format " +
                    (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                    " (supported: .ply, .obj, .gltf, .glb, .json; built-in scenes: " + builtin_scene_names() + ")");
    }
    return scene;
}

}  // namespace thicket
