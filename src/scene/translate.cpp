#include "thicket/scene/translate.h"

#include <string>

#include "thicket/core/vec3.h"

namespace thicket {

Scene translated_scene(const Scene& scene, double offset) {
    TriangleMesh mesh;
    mesh.indices = scene.mesh.indices;
    for (const Vec3& p : scene.mesh.positions) {
        const Vec3d q = Vec3d(p) + Vec3d(offset, offset, offset);
        mesh.positions_double.push_back(q);
        mesh.positions.push_back(q.to_float());
    }
    Scene moved;
    moved.name = scene.name + " moved by " + std::to_string(offset);
    moved.add_mesh(mesh);
    return moved;
}

}  // namespace thicket
