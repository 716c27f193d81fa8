// Wavefront OBJ through tinyobjloader. tinyobj's own triangulation is off: we fan polygons
// ourselves so that triangle ids follow the file order, and we check every index because tinyobj
// only warns about out-of-range ones.
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include <tiny_obj_loader.h>

#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

namespace thicket {
namespace {

/// tinyobj ends its messages with newlines (sometimes doubled); one clean line per message.
/// A missing .mtl yields one "not found" line per material, so only the first few are kept.
std::string tidy(const std::string& text) {
    std::string out;
    std::istringstream in(text);
    std::string line;
    int kept = 0, dropped = 0;
    while (std::getline(in, line)) {
        while (!line.empty() && (line.back() == '\r' || line.back() == '.' || line.back() == ' '))
            line.pop_back();
        if (line.empty()) continue;
        if (kept == 3) {
            ++dropped;
            continue;
        }
        out += (out.empty() ? "" : "; ") + line;
        ++kept;
    }
    if (dropped) out += " (and " + std::to_string(dropped) + " more)";
    return out;
}

Material convert(const tinyobj::material_t& m) {
    Material out;
    out.name = m.name;
    out.diffuse = {float(m.diffuse[0]), float(m.diffuse[1]), float(m.diffuse[2])};
    out.specular = {float(m.specular[0]), float(m.specular[1]), float(m.specular[2])};
    out.emission = {float(m.emission[0]), float(m.emission[1]), float(m.emission[2])};
    out.shininess = float(m.shininess);
    out.ior = float(m.ior);
    return out;
}

}  // namespace

/// Reads an OBJ file (and its .mtl materials when found); polygons are fan-triangulated in
/// file order. Throws thicket::Error("<path>: ...") when the file cannot be read or parsed.
TriangleMesh load_obj(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw FileError(path + ": is a directory, not an OBJ file");

    tinyobj::ObjReaderConfig config;
    config.triangulate = false;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    const bool ok = reader.ParseFromFile(path, config);
    if (!ok) {
        const std::string why = tidy(reader.Error());
        throw Error(path + ": " + (why.empty() ? std::string("cannot parse OBJ file") : why));
    }

    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const size_t vertex_count = attrib.vertices.size() / 3;
    TriangleMesh mesh;
    mesh.positions.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i)
        mesh.positions[i] = {attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]};

    const std::vector<tinyobj::material_t>& materials = reader.GetMaterials();
    for (const tinyobj::material_t& m : materials) mesh.materials.push_back(convert(m));
    uint32_t default_material = uint32_t(-1);  // appended on first use

    size_t face_number = 0;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const tinyobj::mesh_t& m = shape.mesh;
        size_t offset = 0;
        for (size_t f = 0; f < m.num_face_vertices.size(); ++f, ++face_number) {
            const size_t n = m.num_face_vertices[f];
            if (offset + n > m.indices.size())
                throw Error(path + ": face " + std::to_string(face_number) +
                            " is inconsistent (tinyobjloader)");
            for (size_t k = 0; k < n; ++k) {
                const int vi = m.indices[offset + k].vertex_index;
                if (vi < 0)
                    throw Error(path + ": face " + std::to_string(face_number) +
                                ": a relative vertex index points before the first vertex");
                if (size_t(vi) >= vertex_count)
                    throw Error(path + ": face " + std::to_string(face_number) + ": vertex index " +
                                std::to_string(int64_t(vi) + 1) + " is out of range (" +
                                std::to_string(vertex_count) + " vertices)");
            }
            uint32_t material = uint32_t(-1);
            const int id = f < m.material_ids.size() ? m.material_ids[f] : -1;
            if (id >= 0 && size_t(id) < materials.size()) {
                material = uint32_t(id);
            } else if (!materials.empty()) {
                if (default_material == uint32_t(-1)) {
                    default_material = uint32_t(mesh.materials.size());
                    Material fallback;
                    fallback.name = "default";
                    mesh.materials.push_back(fallback);
                }
                material = default_material;
            }
            for (size_t k = 2; k < n; ++k) {
                mesh.indices.push_back(uint32_t(m.indices[offset].vertex_index));
                mesh.indices.push_back(uint32_t(m.indices[offset + k - 1].vertex_index));
                mesh.indices.push_back(uint32_t(m.indices[offset + k].vertex_index));
                if (material != uint32_t(-1)) mesh.material_ids.push_back(material);
            }
            offset += n;
        }
    }
    // A missing .mtl or an unknown usemtl only costs the colours: say so, but keep the geometry.
    const std::string notes = tidy(reader.Warning() + "\n" + reader.Error());
    if (!notes.empty()) std::cerr << path << ": warning: " << notes << '\n';
    return mesh;
}

}  // namespace thicket
