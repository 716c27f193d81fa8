// The shape types of the JSON scene format, one parser each (fields documented in
// docs/shapes.md). Adding a kernel: a parse function that reads its fields with ShapeFields and
// appends it with scene.add_shape(), and one row in kParsers.
#include <algorithm>
#include <cmath>
#include <string>

#include "json_fields.h"
#include "thicket/core/error.h"
#include "thicket/prims/control_mesh.h"
#include "thicket/prims/teapot_patches.h"
#include "thicket/scene/loaders.h"

namespace thicket::json_scene {

namespace {

/// "transform": 16 numbers, a row-major 4x4 affine matrix (last row 0 0 0 1) with an invertible
/// linear part, applied to points (p' = M [p 1]): mesh vertices, Bezier control points (patches
/// are affinely invariant, so that is exact), subdivision cage vertices.
void apply_transform(ShapeFields& f, std::vector<Vec3>& points) {
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
    for (Vec3& p : points) {
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
    if (f.has("transform")) apply_transform(f, mesh.positions);
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

/// Runs a kernel's constructor, turning its Error (the kernel's own range checks) into one that
/// names the shape.
template <class Make>
auto construct(ShapeFields& f, Make&& make) {
    try {
        return make();
    } catch (const Error& e) {
        f.fail_shape(e.what());
    }
}

/// {"type": "bezier", "control_points": [16 points], "transform": [16 numbers]}: one bicubic
/// patch, control point (i, j) (i along u, j along v) at index 4 j + i.
void parse_bezier(ShapeFields& f, Scene& scene) {
    std::vector<Vec3> points = f.points("control_points", 16);
    if (f.has("transform")) apply_transform(f, points);
    BezierPatch::ControlPoints cp;
    std::copy(points.begin(), points.end(), cp.begin());
    scene.add_shape(construct(f, [&] { return BezierPatch(cp); }));
}

/// {"type": "teapot-patches", "transform": [16 numbers]}: Newell's 32 patches, y-up, one id each.
void parse_teapot_patches(ShapeFields& f, Scene& scene) {
    std::vector<BezierPatch> patches = teapot_patches();
    if (f.has("transform")) {
        for (BezierPatch& patch : patches) {
            std::vector<Vec3> points(patch.control_points().begin(), patch.control_points().end());
            apply_transform(f, points);
            BezierPatch::ControlPoints cp;
            std::copy(points.begin(), points.end(), cp.begin());
            patch = BezierPatch(cp);
        }
    }
    for (const BezierPatch& patch : patches) scene.add_shape(patch);
}

/// {"type": "subdivision", one of "file": "cage.obj" or ".ply" | "cage": "cube" | "positions" + "faces",
///  "level": 0..8 (3), "transform": [16 numbers]}: one Catmull-Clark surface, one id.
void parse_subdivision(ShapeFields& f, Scene& scene) {
    const bool file = f.has("file"), builtin = f.has("cage"), inline_mesh = f.has("positions");
    const bool faces = f.has("faces");
    if (int(file) + int(builtin) + int(inline_mesh) != 1)
        f.fail_shape("needs exactly one cage: 'file' (an OBJ or PLY of polygons), 'cage' (\"cube\"), or 'positions' with 'faces'");
    if (faces && !inline_mesh) f.fail("faces", "only goes with 'positions'");
    ControlMesh cage;
    if (file) {
        const std::string path = f.path("file");
        try {
            cage = load_control_mesh(path);
        } catch (const Error& e) {
            f.fail("file", e.what());
        }
    } else if (builtin) {
        const std::string name = f.string("cage");
        if (name != "cube") f.fail("cage", "unknown built-in cage '" + name + "' (known: cube)");
        cage = cube_control_mesh();
    } else {
        cage.positions = f.points("positions", ShapeFields::kAnyCount);
        for (const std::vector<uint32_t>& face : f.index_lists("faces")) {
            cage.face_sizes.push_back(uint32_t(face.size()));
            cage.indices.insert(cage.indices.end(), face.begin(), face.end());
        }
    }
    const int level = f.has("level") ? int(f.integer("level", 0, kMaxSubdivisionLevel)) : 3;
    if (f.has("transform")) apply_transform(f, cage.positions);
    scene.add_shape(construct(f, [&] { return SubdivisionSurface(cage, level); }));
}

/// The placement and method fields every implicit surface has: "center", "scale", "method",
/// "epsilon", "max_steps".
ImplicitOptions implicit_options(ShapeFields& f) {
    ImplicitOptions o;
    if (f.has("center")) o.center = f.vec3("center");
    if (f.has("scale")) o.scale = f.positive("scale");
    if (f.has("method")) {
        const std::string m = f.string("method");
        if (m != "interval" && m != "sphere-tracing")
            f.fail("method", "must be \"interval\" or \"sphere-tracing\", got \"" + m + "\"");
        o.method = parse_implicit_method(m);
    }
    if (f.has("epsilon")) {
        o.epsilon = f.number("epsilon");
        if (!(o.epsilon >= 0.0)) f.fail("epsilon", "must be >= 0 (0: 1e-6 of the box's diagonal), got " + format_number(o.epsilon));
    }
    if (f.has("max_steps")) o.max_steps = int(f.integer("max_steps", 1, 1 << 24));
    return o;
}

/// {"type": "implicit", "surface": "tangle-cube" | "barth-sextic", "clip": 1 (Barth only), ...}
void parse_implicit(ShapeFields& f, Scene& scene) {
    const std::string surface = f.string("surface");
    if (surface != "tangle-cube" && surface != "barth-sextic")
        f.fail("surface", "must be \"tangle-cube\" or \"barth-sextic\", got \"" + surface + "\"");
    double clip = 1.0;
    if (f.has("clip")) {
        if (surface != "barth-sextic") f.fail("clip", "only applies to the barth-sextic surface");
        clip = f.positive("clip");
    }
    const ImplicitOptions options = implicit_options(f);
    scene.add_shape(construct(f, [&] { return Implicit(surface, options, clip); }));
}

/// {"type": "blobs", "centers": [points], "radii": [numbers], "weights": [numbers] (all 1),
///  "threshold": 0.5, ...}: one id for the whole sum.
void parse_blobs(ShapeFields& f, Scene& scene) {
    const std::vector<Vec3> centers = f.points("centers", ShapeFields::kAnyCount);
    const std::vector<double> radii = f.numbers("radii", centers.size());
    const std::vector<double> weights =
        f.has("weights") ? f.numbers("weights", centers.size()) : std::vector<double>(centers.size(), 1.0);
    BlobSum sum;
    for (size_t i = 0; i < centers.size(); ++i) {
        if (!(radii[i] > 0.0)) f.fail("radii", "element " + std::to_string(i) + " must be positive, got " + format_number(radii[i]));
        if (!(weights[i] > 0.0))
            f.fail("weights", "element " + std::to_string(i) + " must be positive, got " + format_number(weights[i]));
        sum.blobs.push_back({{centers[i].x, centers[i].y, centers[i].z}, radii[i], weights[i]});
    }
    if (f.has("threshold")) sum.threshold = f.positive("threshold");
    const ImplicitOptions options = implicit_options(f);
    scene.add_shape(construct(f, [&] { return Blobs(std::move(sum), options); }));
}

/// The placement and marching fields both fractals have: "center", "scale", "iterations",
/// "epsilon", "step_factor", "max_steps".
void fractal_march(ShapeFields& f, FractalMarch& m) {
    if (f.has("center")) m.center = f.vec3("center");
    if (f.has("scale")) m.scale = f.positive("scale");
    if (f.has("iterations")) m.iterations = int(f.integer("iterations", 1, 1000));
    if (f.has("epsilon")) m.epsilon = f.positive("epsilon");
    if (f.has("step_factor")) {
        m.step_factor = f.positive("step_factor");
        if (m.step_factor > 1.0) f.fail("step_factor", "must be in (0, 1], got " + format_number(m.step_factor));
    }
    if (f.has("max_steps")) m.max_steps = int(f.integer("max_steps", 1, 1 << 24));
}

/// {"type": "julia", "c": [4 numbers], "w": 0, "bailout": 4, ...}
void parse_julia(ShapeFields& f, Scene& scene) {
    Julia::Params p;
    if (f.has("c")) {
        const std::vector<double> c = f.numbers("c", 4);
        std::copy(c.begin(), c.end(), p.c.begin());
    }
    if (f.has("w")) p.w = f.number("w");
    if (f.has("bailout")) p.bailout = f.positive("bailout");
    fractal_march(f, p.march);
    scene.add_shape(construct(f, [&] { return Julia(p); }));
}

/// {"type": "mandelbulb", "power": 8, "bailout": 2, ...}
void parse_mandelbulb(ShapeFields& f, Scene& scene) {
    Mandelbulb::Params p;
    if (f.has("power")) p.power = f.number("power");
    if (f.has("bailout")) p.bailout = f.positive("bailout");
    fractal_march(f, p.march);
    scene.add_shape(construct(f, [&] { return Mandelbulb(p); }));
}

constexpr ShapeParser kParsers[] = {
    {"mesh", parse_mesh},
    {"sphere", parse_sphere},
    {"torus", parse_torus},
    {"bezier", parse_bezier},
    {"teapot-patches", parse_teapot_patches},
    {"subdivision", parse_subdivision},
    {"implicit", parse_implicit},
    {"blobs", parse_blobs},
    {"julia", parse_julia},
    {"mandelbulb", parse_mandelbulb},
};

}  // namespace

std::span<const ShapeParser> shape_parsers() { return kParsers; }

}  // namespace thicket::json_scene
