#pragma once
/// Chooses the primitive set a structure is instantiated with, from the scene and the spec's
/// `isect` option. Structures are class templates over a PrimitiveSet; this is where a scene's
/// content picks the instantiation: triangle-only scenes get the Triangles fast path, scenes with
/// shapes the mixed set (triangles and shapes behind one id space). Private to the library
/// (src/ is its private include directory): only the register_*.cpp files use it, mostly through
/// make_structure() and set_build_and_load().
#include <istream>
#include <memory>
#include <type_traits>
#include <utility>

#include "accel/option_fields.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/prims/mixed.h"
#include "thicket/prims/primitive_set.h"
#include "thicket/prims/triangles.h"

namespace thicket {

/// The `isect` option every structure takes (registry.cpp appends it to each entry).
inline constexpr Choice<TriangleTest> kTriangleTests[] = {
    {"moller", TriangleTest::Moller},
    {"watertight", TriangleTest::Watertight},
};

/// The `precision` option of brute and bvh: float (the structures every other option describes)
/// or double (vertices, boxes and ray arithmetic in double; triangle scenes only).
enum class Precision { Float, Double };
inline constexpr Choice<Precision> kPrecisions[] = {
    {"float", Precision::Float},
    {"double", Precision::Double},
};
inline OptionInfo precision_option() {
    return choice_option("precision",
                         "float, or double: vertices (the file's own doubles when it has them), boxes and ray "
                         "arithmetic in double, for coordinates far from the origin; triangle scenes only",
                         Precision::Float, kPrecisions);
}
inline bool wants_double(const AccelSpec& spec) { return spec.choice("precision", kPrecisions) == Precision::Double; }

/// Calls make(TrianglesD<Test>) for the triangle test `spec` asks for; throws Error naming the
/// spec and scene for a scene with shapes (their double forms do not exist).
template <class Make>
std::unique_ptr<Accel> with_double_triangles(const Scene& scene, const AccelSpec& spec, Make&& make) {
    if (scene.has_shapes())
        throw Error(spec.str() + ": precision=double takes triangle scenes only, and '" + scene.name + "' has " +
                    std::to_string(scene.shapes.size()) + " shapes (use precision=float)");
    if (spec.choice("isect", kTriangleTests) == TriangleTest::Watertight)
        return make(TrianglesD<TriangleTest::Watertight>(scene.mesh));
    return make(TrianglesD<TriangleTest::Moller>(scene.mesh));
}

/// Calls make(prims) with the primitive set matching `spec` for `scene`, returns its result.
template <class Make>
std::unique_ptr<Accel> with_primitives(const Scene& scene, const AccelSpec& spec, Make&& make) {
    const bool watertight = spec.choice("isect", kTriangleTests) == TriangleTest::Watertight;
    if (scene.has_shapes())
        return make(MixedPrimitives(scene.mesh, scene.shapes, scene.runs, scene.name,
                                    watertight ? TriangleTest::Watertight : TriangleTest::Moller));
    if (watertight) return make(Triangles<TriangleTest::Watertight>(scene.mesh));
    return make(Triangles<TriangleTest::Moller>(scene.mesh));
}

/// Makes Structure<P>(prims, args...) over the primitive set P that `spec` asks for on `scene`
/// (with_primitives()); `args` are passed on once.
template <template <PrimitiveSet> class Structure, class... Args>
std::unique_ptr<Accel> make_structure(const Scene& scene, const AccelSpec& spec, Args&&... args) {
    return with_primitives(scene, spec, [&](auto prims) -> std::unique_ptr<Accel> {
        return std::make_unique<Structure<decltype(prims)>>(std::move(prims), std::forward<Args>(args)...);
    });
}

/// The registration of a structure built from its option fields and restored from its saved
/// data: info.build makes Structure(prims, settings), info.load Structure(prims, saved, settings)
/// where the structure takes its settings beside the saved data (those that check or rebuild
/// from them), else Structure(prims, saved); `settings` is read_settings(fields, spec) and
/// `saved` read(in, the scene's primitive count).
template <template <PrimitiveSet> class Structure, class Settings, class Read>
void set_build_and_load(AccelInfo& info, const OptionFields<Settings>& fields, Read read) {
    info.build = [fields](const Scene& scene, const AccelSpec& spec) {
        return make_structure<Structure>(scene, spec, read_settings(fields, spec));
    };
    info.load = [fields, read](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        auto saved = read(in, scene.primitive_count());
        return with_primitives(scene, spec, [&](auto prims) -> std::unique_ptr<Accel> {
            using P = decltype(prims);
            if constexpr (std::is_constructible_v<Structure<P>, P, decltype(saved), const Settings&>)
                return std::make_unique<Structure<P>>(std::move(prims), std::move(saved),
                                                      read_settings(fields, spec));
            else
                return std::make_unique<Structure<P>>(std::move(prims), std::move(saved));
        });
    };
}

}  // namespace thicket
