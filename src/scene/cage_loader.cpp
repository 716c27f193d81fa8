// Subdivision cages from OBJ and PLY files: the polygons as written (no triangulation), so the
// limit surface is the one of the file's faces. Lives with the loaders so that prims/ (which
// validates and evaluates cages) never depends on scene/.
#include <cctype>
#include <filesystem>

#include "obj_reader.h"
#include "thicket/core/error.h"
#include "thicket/prims/control_mesh.h"
#include "thicket/scene/loaders.h"

namespace thicket {

namespace {

/// The cage of polygons `face_sizes` over `indices` into `positions`, keeping only the vertices
/// some face uses (renumbered in order of first use), validated. Errors start with `path`.
ControlMesh compact_cage(const std::string& path, const std::vector<Vec3>& positions,
                         const std::vector<uint32_t>& face_sizes, const std::vector<uint32_t>& indices) {
    ControlMesh cage;
    std::vector<uint32_t> remap(positions.size(), uint32_t(-1));
    size_t offset = 0;
    for (size_t f = 0; f < face_sizes.size(); ++f) {
        const size_t n = face_sizes[f];
        if (offset + n > indices.size()) throw Error(path + ": face " + std::to_string(f) + " is inconsistent");
        for (size_t k = 0; k < n; ++k) {
            const uint32_t vi = indices[offset + k];
            if (vi >= positions.size())
                throw Error(path + ": face " + std::to_string(f) + ": vertex index " + std::to_string(uint64_t(vi) + 1) +
                            " is out of range (" + std::to_string(positions.size()) + " vertices)");
            if (remap[vi] == uint32_t(-1)) {
                remap[vi] = uint32_t(cage.positions.size());
                cage.positions.push_back(positions[vi]);
            }
            cage.indices.push_back(remap[vi]);
        }
        cage.face_sizes.push_back(uint32_t(n));
        offset += n;
    }
    try {
        validate_control_mesh(cage);
    } catch (const Error& e) {
        throw Error(path + ": " + e.what() + " (vertex and face numbers count from 0 in file order of first use)");
    }
    return cage;
}

ControlMesh load_obj_cage(const std::string& path) {
    const obj::ObjData data = obj::read_obj(path, /*materials=*/false);
    return compact_cage(path, data.positions, data.face_sizes, data.indices);
}

/// The PLY's faces rebuilt from their fans (face of n vertices = n - 2 triangles v0 v[k-1] v[k]).
ControlMesh load_ply_cage(const std::string& path) {
    std::vector<uint32_t> face_sizes;
    const TriangleMesh fans = load_ply(path, face_sizes);
    std::vector<uint32_t> indices;
    size_t t = 0;
    for (uint32_t n : face_sizes) {
        const uint32_t* tri = fans.indices.data() + 3 * t;
        indices.insert(indices.end(), {tri[0], tri[1], tri[2]});
        for (uint32_t k = 1; k + 2 < n; ++k) indices.push_back(tri[3 * k + 2]);
        t += n - 2;
    }
    return compact_cage(path, fans.positions, face_sizes, indices);
}

}  // namespace

ControlMesh load_control_mesh(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a cage file");
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".obj") return load_obj_cage(path);
    if (ext == ".ply") return load_ply_cage(path);
    throw Error(path + ": a cage is read from an OBJ or PLY file (its polygons, untriangulated), not '" + ext + "'");
}

}  // namespace thicket
