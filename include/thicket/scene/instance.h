#pragma once
/// Instances: a geometry of a scene placed again under an affine transform (two-level
/// instancing, instances/instances.h). Plain records, so that a Scene can carry them (JSON scenes'
/// `instances`) without depending on the structures.
#include <cstdint>
#include <string>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket {

/// An affine map world = A * p + b, as the 3x4 row-major matrix [A | b] (Embree's and glTF's
/// 3x4 form, the top three rows of a 4x4).
struct Affine {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

    /// A * p + b.
    Vec3 point(Vec3 p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    /// A * v (a direction: no translation).
    Vec3 vector(Vec3 v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    /// A^T * v: with the inverse's A, what carries a normal from object to world space.
    Vec3 transposed_vector(Vec3 v) const {
        return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z, m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
                m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
    }
};

/// Transforms whose linear part A has a condition number ||A||_F * ||A^-1||_F (Frobenius norms;
/// 3 for a rotation or a uniform scale) above this are refused as near-singular: a ray carried
/// into such an instance's space loses about log10(condition) of float's 7 digits, and the hits
/// would no longer match the flattened scene's.
inline constexpr double kMaxTransformCondition = 1e4;

/// ||A||_F * ||A^-1||_F of the linear part, computed in double; +infinity for a singular one and
/// NaN for one with a non-finite entry.
double transform_condition(const Affine& t);

/// The inverse of `t`. Throws Error starting with `what` (e.g. "instance 3") for a transform with
/// a non-finite entry or a condition number (transform_condition) above kMaxTransformCondition,
/// giving the number and the limit.
Affine checked_inverse(const Affine& t, const std::string& what);

/// det(A) of the linear part: negative for a mirroring transform (which reverses the winding of
/// the triangles it carries).
double transform_determinant(const Affine& t);

/// The box holding `t` applied to every point of `box` (its eight corners' images).
Aabb transform_box(const Affine& t, const Aabb& box);

/// What carries world rays into an instance's space: local = A^-1 (p - b) for the transform
/// world = A p + b. The translation comes off first, exactly when p lies within a factor of two of
/// b on each axis (Sterbenz), as the origin of a ray leaving the instance's own surface does; the
/// inverse's form A^-1 p + (-A^-1 b) would cancel there and keep an error of ulp(|A^-1 b|),
/// a t off by 0.4% for a ray starting 0.003 units from the surface it hits (the forest's diffuse
/// set). Every path that carries a ray into an instance (traversal, probes, normals) uses this
/// one, so that they all see the same local ray to the bit.
struct RayToInstance {
    float inverse[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  ///< A^-1
    Vec3 offset;                                               ///< b

    /// The world ray in the instance's space over [ray.tmin, tmax]: t keeps its meaning.
    Ray ray(const Ray& world, float tmax) const { return Ray{point(world.org), world.tmin, vector(world.dir), tmax}; }
    Vec3 point(Vec3 p) const { return vector(p - offset); }
    Vec3 vector(Vec3 v) const {
        return {inverse[0][0] * v.x + inverse[0][1] * v.y + inverse[0][2] * v.z,
                inverse[1][0] * v.x + inverse[1][1] * v.y + inverse[1][2] * v.z,
                inverse[2][0] * v.x + inverse[2][1] * v.y + inverse[2][2] * v.z};
    }
};

/// The RayToInstance of `transform`, whose inverse (checked_inverse) is `inverse`.
RayToInstance ray_to_instance(const Affine& transform, const Affine& inverse);

/// One placement of a scene's geometry `geometry` (Scene::geometries' index) under `transform`
/// (object to world).
struct Instance {
    uint32_t geometry = 0;
    Affine transform;
};

struct Scene;

/// A hit of a scene with instances taken back to its prototype: the instance, the ray in the
/// instance's space and the hit with the prototype scene's primitive id. Default-constructed it
/// stands for no instance, and to_world() returns a normal unchanged.
struct InstancePlace {
    bool placed = false;
    Affine inverse;
    bool mirrored = false;
    Ray ray;
    Hit hit;
    /// The world normal of the object-space unit normal `n`: carried by the inverse transpose,
    /// and for a triangle's winding-order normal (`winding`) flipped when the transform mirrors.
    Vec3 to_world(Vec3 n, bool winding) const;
};

/// Bounds of every instance of `scene` in the world (Scene::bounds() of a scene with instances).
Aabb instanced_bounds(const Scene& scene);

/// Fills `place` for `hit` of the world ray `ray` on `scene` (which has instances; hit.prim a
/// flattened id); false for a miss or an id past the instances' primitives.
bool place_instanced_hit(const Scene& scene, const Ray& ray, const Hit& hit, InstancePlace& place);

}  // namespace thicket
