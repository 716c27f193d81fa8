// Wavefront OBJ meshes through the strict reader (obj_reader.h). Polygons are fanned here, so
// that triangle ids follow the file order.
#include <iostream>
#include <string>

#include "obj_reader.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

namespace thicket {

/// Reads an OBJ file (and its .mtl materials when found); polygons are fan-triangulated in
/// file order. Throws thicket::Error("<path>: ...") when the file cannot be read or parsed.
TriangleMesh load_obj(const std::string& path) {
    obj::ObjData obj = obj::read_obj(path, /*materials=*/true);

    TriangleMesh mesh;
    mesh.positions = std::move(obj.positions);
    mesh.materials = std::move(obj.materials);
    const auto named = uint32_t(mesh.materials.size());
    uint32_t default_material = uint32_t(-1);  // appended on first use
    size_t triangles = 0;
    for (uint32_t n : obj.face_sizes) triangles += n - 2;
    mesh.indices.reserve(3 * triangles);
    size_t offset = 0;
    for (size_t f = 0; f < obj.face_sizes.size(); ++f) {
        const uint32_t n = obj.face_sizes[f];
        // Faces without a (known) material get "default" once the file has materials at all.
        uint32_t material = uint32_t(-1);
        const int32_t id = obj.face_materials[f];
        if (id >= 0 && uint32_t(id) < named) {
            material = uint32_t(id);
        } else if (named > 0) {
            if (default_material == uint32_t(-1)) {
                default_material = uint32_t(mesh.materials.size());
                Material fallback;
                fallback.name = "default";
                mesh.materials.push_back(fallback);
            }
            material = default_material;
        }
        const uint32_t* v = obj.indices.data() + offset;
        for (uint32_t k = 2; k < n; ++k) {
            mesh.indices.insert(mesh.indices.end(), {v[0], v[k - 1], v[k]});
            if (material != uint32_t(-1)) mesh.material_ids.push_back(material);
        }
        offset += n;
    }
    // A missing .mtl or an unknown usemtl only costs the colours: say so, but keep the geometry.
    for (size_t i = 0; i < obj.warnings.size() && i < 3; ++i) std::cerr << path << ": warning: " << obj.warnings[i] << '\n';
    if (obj.warnings.size() > 3)
        std::cerr << path << ": warning: (and " << obj.warnings.size() - 3 << " more)\n";
    return mesh;
}

}  // namespace thicket
