#pragma once
/// The mixed primitive set: triangles and shapes behind one PrimitiveSet, so every structure
/// holds spheres, tori, ... next to triangles. Built from plain geometry (mesh, shapes, id runs),
/// not from a Scene. Chosen by with_primitives() only for scenes that have shapes; triangle-only
/// scenes keep the Triangles fast path.
///
/// One type for both triangle tests, picked at run time (a branch the predictor always gets right):
/// scenes with shapes are the rarer case, and a second instantiation of every structure over a
/// second mixed type was a quarter of the library's structure code to compile.
///
/// Layout: triangles as in Triangles (36 bytes each), shapes in one array per kernel type
/// (no variant padding: a sphere stays 16 bytes next to bigger kernels), and one 32-bit reference
/// per primitive id: the kind in the top 4 bits (0 triangle, k the k-th alternative of Shape
/// plus one), the index within its array below.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/core/ray_box.h"
#include "thicket/geometry/mesh.h"
#include "thicket/geometry/prim_runs.h"
#include "thicket/prims/shapes.h"
#include "thicket/prims/triangles.h"

namespace thicket {

namespace detail {
template <class V>
struct ShapeArrays;
template <class... S>
struct ShapeArrays<std::variant<S...>> {
    using type = std::tuple<std::vector<S>...>;
};
}  // namespace detail

class MixedPrimitives {
public:
    static constexpr uint32_t kKindShift = 28;
    static constexpr uint32_t kIndexMask = (1u << kKindShift) - 1;
    static constexpr size_t kKinds = std::variant_size_v<Shape>;
    static_assert(kKinds + 1 < 16, "the kind must fit the top 4 bits of a reference");

private:
    // Before their callers: a non-template class's members see a deduced return type only once
    // its definition has been read.
    /// Calls f(kernel) for the shape behind reference r (kind > 0), dispatching on the kind.
    template <class F>
    decltype(auto) visit_shape(uint32_t r, F&& f) const {
        return visit_kind(r >> kKindShift, r & kIndexMask, f, std::make_index_sequence<kKinds>{});
    }
    template <class F, size_t... K>
    decltype(auto) visit_kind(uint32_t kind, uint32_t index, F& f, std::index_sequence<K...>) const {
        using R = decltype(f(std::get<0>(shapes_)[0]));
        R result{};
        // One comparison per kernel type: a switch the compiler builds from the fold.
        (void)((kind == K + 1 ? (result = f(std::get<K>(shapes_)[index]), true) : false) || ...);
        return result;
    }

public:
    MixedPrimitives() = default;
    /// The triangles of `mesh` (tested with `test`) and the `shapes`, with ids ordered by `runs`
    /// (see locate_prim). Throws Error starting with `name` when either count does not fit a reference.
    MixedPrimitives(const TriangleMesh& mesh, const std::vector<Shape>& shapes, const std::vector<PrimRun>& runs,
                    const std::string& name, TriangleTest test)
        : test_(test), tris_(mesh) {
        const size_t n = mesh.triangle_count() + shapes.size();
        if (mesh.triangle_count() > kIndexMask || shapes.size() > kIndexMask)
            throw Error(name + ": a scene with shapes holds at most " + std::to_string(kIndexMask) +
                        " triangles and as many shapes");
        refs_.resize(n);
        std::vector<uint32_t> shape_refs(shapes.size());
        for (size_t s = 0; s < shapes.size(); ++s)
            std::visit(
                [&](const auto& k) {
                    auto& arr = std::get<std::vector<std::decay_t<decltype(k)>>>(shapes_);
                    shape_refs[s] = (uint32_t(shapes[s].index() + 1) << kKindShift) | uint32_t(arr.size());
                    arr.push_back(k);
                },
                shapes[s]);
        const auto triangles = uint32_t(mesh.triangle_count());
        for (uint32_t i = 0; i < n; ++i) {
            const PrimRef r = locate_prim(runs, triangles, i);
            refs_[i] = r.shape ? shape_refs[r.index] : r.index;
        }
    }

    TriangleTest triangle_test() const { return test_; }
    size_t size() const { return refs_.size(); }
    size_t bytes() const {
        size_t b = tris_.bytes() + refs_.size() * sizeof(uint32_t);
        std::apply([&](const auto&... arr) { ((b += arr.size() * sizeof(arr[0])), ...); }, shapes_);
        return b;
    }

    Aabb bounds(uint32_t i) const {
        const uint32_t r = refs_[i];
        if ((r >> kKindShift) == 0) return tris_.bounds(r);
        return visit_shape(r, [](const auto& s) { return s.bounds(); });
    }
    Vec3 centroid(uint32_t i) const {
        const uint32_t r = refs_[i];
        if ((r >> kKindShift) == 0) return tris_.centroid(r);
        return bounds(i).center();
    }
    /// The vertices of primitive i when it is a triangle, else nothing (structures that take
    /// only triangles, such as the tetrahedralization, leave the shapes to another structure).
    std::optional<std::array<Vec3, 3>> triangle_of(uint32_t i) const {
        const uint32_t r = refs_[i];
        if ((r >> kKindShift) != 0) return std::nullopt;
        return tris_.triangle(r);
    }
    /// Exact bounds of a triangle's part inside `box`; a shape's bounds clipped to it.
    Aabb clip(uint32_t i, const Aabb& box) const {
        const uint32_t r = refs_[i];
        if ((r >> kKindShift) == 0) return tris_.clip(r, box);
        return intersection(bounds(i), box);
    }

    /// Closest-hit update: if primitive i is hit within [ray.tmin, hit.t], overwrite hit.
    bool intersect(uint32_t i, const Ray& ray, Hit& hit) const {
        const uint32_t r = refs_[i];
        if ((r >> kKindShift) == 0) {
            const bool found = test_ == TriangleTest::Watertight
                                   ? tris_.intersect_using<TriangleTest::Watertight>(r, ray, hit)
                                   : tris_.intersect_using<TriangleTest::Moller>(r, ray, hit);
            if (!found) return false;
            hit.prim = i;
            return true;
        }
        ShapeHit sh;
        if (!visit_shape(r, [&](const auto& s) { return s.intersect(ray, hit.t, sh) && plausible(s, ray, sh.t); }))
            return false;
        hit = {sh.t, sh.u, sh.v, i};
        return true;
    }
    /// Any-hit: is primitive i hit within [ray.tmin, ray.tmax]?
    bool occludes(uint32_t i, const Ray& ray) const {
        const uint32_t r = refs_[i];
        if ((r >> kKindShift) == 0)
            return test_ == TriangleTest::Watertight ? tris_.occludes_using<TriangleTest::Watertight>(r, ray)
                                                     : tris_.occludes_using<TriangleTest::Moller>(r, ray);
        ShapeHit sh;
        return visit_shape(r, [&](const auto& s) { return s.intersect(ray, ray.tmax, sh) && plausible(s, ray, sh.t); });
    }

    /// The same rule as for triangles (hit_within_bounds): the hit lies in the ray's interval
    /// through the shape's bounds, the interval every structure tests on the way down.
    template <class S>
    static bool plausible(const S& s, const Ray& ray, float t) {
        return hit_within_bounds(ray, t, s.bounds());
    }

private:
    TriangleTest test_ = TriangleTest::Moller;
    Triangles<> tris_;  ///< storage only: its test is test_
    typename detail::ShapeArrays<Shape>::type shapes_;
    std::vector<uint32_t> refs_;
};

}  // namespace thicket
