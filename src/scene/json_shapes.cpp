// The shape types of the JSON scene format, one parser each (fields documented in
// docs/shapes.md). Adding a kernel: a parse function that reads its fields with ShapeFields and
// appends it with scene.add_shape(), and one row in kParsers.
#include <algorithm>
#include <cmath>
#include <string>

#include "json_fields.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

namespace thicket::json_scene {

namespace {

/// "transform": 16 numbers, a row-major 4x4 affine matrix (last row 0 0 0 1) with an invertible
/// linear part, applied to the mesh's positions (p' = M [p 1]).
void apply_transform(ShapeFields& f, TriangleMesh& mesh) {
    const std::vector<double> m = f.numbers("transform", 16);
    if (m[12] != 0.0 || m[13] != 0.0 || m[14] != 0.0 || m[15] != 1.0)
        f.fail("transform", "the last row must be 0 0 0 1 (an affine transform), got " + format_number(m[12]) + " " +
                                format_number(m[13]) + " " + format_number(m[14]) + " " + format_number(m[15]));
    // Invertible relative to the matrix's scale (|det| <= largest row length cubed, equal for a
    // rotation times a uniform scale): a uniformly tiny scale is fine, a squashed axis is not.
    const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                       m[2] * (m[4] * m[9] - m[5] * m[8]);
    double scale = 0.0;
    for (int r = 0; r < 3; ++r)
        scale = std::max(scale, std::sqrt(m[4 * r] * m[4 * r] + m[4 * r + 1] * m[4 * r + 1] + m[4 * r + 2] * m[4 * r + 2]));
    if (!(std::fabs(det) > 1e-9 * scale * scale * scale))
        f.fail("transform", "the upper-left 3x3 part is singular or nearly so (determinant " + format_number(det) +
                                "): the mesh would be flattened");
    for (Vec3& p : mesh.positions) {
        double out[3];
        for (int r = 0; r < 3; ++r) out[r] = m[4 * r] * p.x + m[4 * r + 1] * p.y + m[4 * r + 2] * p.z + m[4 * r + 3];
        const Vec3 q{float(out[0]), float(out[1]), float(out[2])};
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            f.fail("transform", "moves a vertex out of the float range");
        p = q;
    }
}

/// {"type": "mesh", "file": "bunny.ply", "transform": [16 numbers]}: its triangles, in order.
void parse_mesh(ShapeFields& f, Scene& scene) {
    const std::string file = f.path("file");
    TriangleMesh mesh;
    try {
        mesh = load_mesh(file);
    } catch (const Error& e) {
        f.fail("file", e.what());
    }
    if (f.has("transform")) apply_transform(f, mesh);
    scene.add_mesh(mesh);
}

/// {"type": "sphere", "center": [x, y, z], "radius": r}
void parse_sphere(ShapeFields& f, Scene& scene) {
    Sphere s;
    s.center = f.vec3("center");
    s.radius = f.positive("radius");
    scene.add_shape(s);
}

/// {"type": "torus", "center": [x, y, z], "axis": [x, y, z], "major_radius": R, "minor_radius": r}
void parse_torus(ShapeFields& f, Scene& scene) {
    Torus t;
    t.center = f.vec3("center");
    t.axis = f.has("axis") ? f.direction("axis") : Vec3{0.0f, 1.0f, 0.0f};
    t.major = f.positive("major_radius");
    t.minor = f.positive("minor_radius");
    if (!(t.minor < t.major))
        f.fail("minor_radius", "must be less than major_radius (" + format_number(t.major) + ") for a ring torus, got " +
                                   format_number(t.minor));
    scene.add_shape(t);
}

constexpr ShapeParser kParsers[] = {
    {"mesh", parse_mesh},
    {"sphere", parse_sphere},
    {"torus", parse_torus},
};

}  // namespace

std::span<const ShapeParser> shape_parsers() { return kParsers; }

}  // namespace thicket::json_scene
