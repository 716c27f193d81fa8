// Scene loading entry point: built-in names first, then dispatch on the file extension.
#include "thicket/scene/scene.h"

#include <bit>
#include <cctype>
#include <filesystem>

#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

namespace thicket {

/// FNV-1a 64 over each triangle's nine vertex floats (as bits), in order, then the triangle count.
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
    return h;
}

const char* builtin_scene_names() { return "cornell"; }

Scene load_scene(const std::string& path_or_builtin) {
    Scene scene;
    scene.name = path_or_builtin;
    if (path_or_builtin == "cornell") {
        scene.mesh = builtin_cornell_box();
        return scene;
    }
    const std::string& path = path_or_builtin;
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) throw Error(path + ": no such file");
    if (fs::is_directory(st)) throw Error(path + ": is a directory, not a scene file");

    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".ply")
        scene.mesh = load_ply(path);
    else if (ext == ".obj")
        scene.mesh = load_obj(path);
    else if (ext == ".gltf" || ext == ".glb")
        scene.mesh = load_gltf(path);
    else
        throw Error(path + ": unknown scene format " +
                    (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                    " (supported: .ply, .obj, .gltf, .glb; built-in scenes: " + builtin_scene_names() + ")");
    return scene;
}

}  // namespace thicket
