#include "thicket/scene/instance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/scene/scene.h"

namespace thicket {

namespace {

/// det and the adjugate's rows of A in double (A^-1 = adj / det).
double det3(const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

void linear_part(const Affine& t, double a[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = t.m[i][j];
}

/// A^-1 in double; false for a singular A.
bool invert3(const double a[3][3], double inv[3][3]) {
    const double d = det3(a);
    if (!(d != 0.0) || !std::isfinite(d)) return false;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            // Cofactor of a[j][i]: the rows and columns other than j and i, cyclically.
            const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            inv[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / d;
        }
    return true;
}

double frobenius(const double a[3][3]) {
    double s = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) s += a[i][j] * a[i][j];
    return std::sqrt(s);
}

}  // namespace

double transform_condition(const Affine& t) {
    for (const auto& row : t.m)
        for (float x : row)
            if (!std::isfinite(x)) return std::numeric_limits<double>::quiet_NaN();
    double a[3][3], inv[3][3];
    linear_part(t, a);
    if (!invert3(a, inv)) return std::numeric_limits<double>::infinity();
    return frobenius(a) * frobenius(inv);
}

double transform_determinant(const Affine& t) {
    double a[3][3];
    linear_part(t, a);
    return det3(a);
}

Affine checked_inverse(const Affine& t, const std::string& what) {
    const double cond = transform_condition(t);
    if (std::isnan(cond)) throw Error(what + ": the transform has a non-finite entry");
    if (!(cond <= kMaxTransformCondition)) {
        std::ostringstream s;
        s << what << ": the transform is singular or nearly so (condition number ||A||*||A^-1|| = " << cond
          << ", the limit is " << kMaxTransformCondition << "); refusing it";
        throw Error(s.str());
    }
    double a[3][3], inv[3][3];
    linear_part(t, a);
    invert3(a, inv);
    Affine r;
    for (int i = 0; i < 3; ++i) {
        double b = 0.0;
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = float(inv[i][j]);
            b -= inv[i][j] * double(t.m[j][3]);
        }
        r.m[i][3] = float(b);
    }
    return r;
}

RayToInstance ray_to_instance(const Affine& transform, const Affine& inverse) {
    RayToInstance r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.inverse[i][j] = inverse.m[i][j];
    r.offset = {transform.m[0][3], transform.m[1][3], transform.m[2][3]};
    return r;
}

Aabb transform_box(const Affine& t, const Aabb& box) {
    Aabb out;
    if (box.empty()) return out;
    for (int c = 0; c < 8; ++c)
        out.grow(t.point({(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                          (c & 4) ? box.max.z : box.min.z}));
    // The corners' images are rounded; pad by more than that rounding so that every point of the
    // exactly transformed box stays inside.
    const Vec3 e = max(abs(out.min), abs(out.max));
    const float pad = 1e-6f * std::max(e.x, std::max(e.y, e.z));
    out.min = out.min - Vec3(pad);
    out.max = out.max + Vec3(pad);
    return out;
}

Vec3 InstancePlace::to_world(Vec3 n, bool winding) const {
    if (!placed || n == Vec3{}) return n;
    Vec3 w = inverse.transposed_vector(n);
    if (winding && mirrored) w = -w;
    const float len = length(w);
    if (!(len > 0.0f) || !std::isfinite(len)) return Vec3{};
    return w / len;
}

bool place_instanced_hit(const Scene& scene, const Ray& ray, const Hit& hit, InstancePlace& place) {
    if (scene.instance_first.size() != scene.instances.size() + 1)
        throw Error("scene '" + scene.name + "': its instances were not added with Scene::add_instance");
    if (!hit.found() || hit.prim >= scene.instanced_primitive_count()) return false;
    const auto it = std::upper_bound(scene.instance_first.begin(), scene.instance_first.end(), uint64_t(hit.prim));
    const size_t i = size_t(it - scene.instance_first.begin()) - 1;
    const Instance& inst = scene.instances[i];
    place.placed = true;
    place.inverse = checked_inverse(inst.transform, "instance " + std::to_string(i));
    place.mirrored = transform_determinant(inst.transform) < 0.0;
    place.ray = ray_to_instance(inst.transform, place.inverse).ray(ray, ray.tmax);
    place.hit = hit;
    place.hit.prim = scene.geometry(inst.geometry).first + uint32_t(hit.prim - scene.instance_first[i]);
    return true;
}

Aabb instanced_bounds(const Scene& scene) {
    // Each geometry's own bounds once, then each instance's image of them.
    std::vector<Aabb> geometry_bounds(scene.geometry_count());
    std::vector<uint8_t> known(scene.geometry_count(), 0);
    Aabb out;
    for (const Instance& inst : scene.instances) {
        if (inst.geometry >= geometry_bounds.size()) continue;
        if (!known[inst.geometry]) {
            const Geometry g = scene.geometry(inst.geometry);
            Aabb b;
            for (uint32_t p = g.first; p < g.first + g.count; ++p) {
                const PrimRef ref = scene.locate(p);
                if (ref.shape) {
                    b.grow(shape_bounds(scene.shapes[ref.index]));
                } else {
                    for (int c = 0; c < 3; ++c) b.grow(scene.mesh.vertex(ref.index, c));
                }
            }
            geometry_bounds[inst.geometry] = b;
            known[inst.geometry] = 1;
        }
        out.grow(transform_box(inst.transform, geometry_bounds[inst.geometry]));
    }
    return out;
}

uint32_t Scene::add_instance(uint32_t geometry_id, const Affine& transform) {
    const std::string what = "scene '" + name + "': instance " + std::to_string(instances.size());
    if (geometry_id >= geometry_count())
        throw Error(what + ": no geometry " + std::to_string(geometry_id) + " (the scene has " +
                    std::to_string(geometry_count()) + ")");
    checked_inverse(transform, what);
    if (instance_first.empty()) instance_first.push_back(0);
    const uint64_t end = instance_first.back() + geometry(geometry_id).count;
    if (end >= kNoPrim)
        throw Error(what + ": the instances would hold " + std::to_string(end) + " primitives, more than the " +
                    std::to_string(kNoPrim - 1) + " a hit's 32-bit primitive id tells apart");
    instance_first.push_back(end);
    instances.push_back({geometry_id, transform});
    return uint32_t(instances.size() - 1);
}

}  // namespace thicket
