// `thicket info` (scene and structure statistics) and `thicket accels` (the registry's listing).
#include <cstdio>
#include <string>
#include <vector>

#include "common.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

struct InfoArgs {
    std::string scene;
    AccelChoice accel;
    bool no_accel = false;
    unsigned threads = 0;
};

/// Geometries, and for a scene with instances how many there are and how much they repeat.
void print_instances(const Scene& scene) {
    std::printf("  geometries           %zu\n", scene.geometry_count());
    if (scene.instances.empty()) return;
    std::vector<uint8_t> used(scene.geometry_count(), 0);
    size_t unique = 0, geometries = 0;
    for (const Instance& inst : scene.instances)
        if (!used[inst.geometry]) {
            used[inst.geometry] = 1;
            ++geometries;
            unique += scene.geometry(inst.geometry).count;
        }
    std::printf("  instances            %zu, placing %zu of the geometries (one no instance places is not drawn)\n",
                scene.instances.size(), geometries);
    std::printf("  unique primitives    %zu (held once, whatever the instances)\n", unique);
    std::printf("  instanced primitives %llu (what the instances place: the flattened scene)\n",
                static_cast<unsigned long long>(scene.instanced_primitive_count()));
}

void print_scene(const Scene& scene) {
    const TriangleMesh& m = scene.mesh;
    size_t zero_area = 0;
    for (size_t t = 0; t < m.triangle_count(); ++t) {
        const Vec3 a = m.vertex(t, 0), n = cross(m.vertex(t, 1) - a, m.vertex(t, 2) - a);
        zero_area += n.x == 0.0f && n.y == 0.0f && n.z == 0.0f;
    }
    const Aabb b = scene.bounds();
    std::printf("\nscene %s\n", scene.name.c_str());
    std::printf("  triangles            %zu\n", m.triangle_count());
    std::printf("  vertices             %zu\n", m.positions.size());
    std::printf("  zero-area triangles  %zu\n", zero_area);
    const VertexCounts bad = count_bad_vertices(scene);
    std::printf("  non-finite vertices  %zu (NaN or infinite: never hit)\n", bad.nonfinite);
    std::printf("  vertices beyond 1e18 %zu (float products overflow: hits may be lost)\n", bad.large);
    if (scene.has_shapes()) {
        // Per type, in the order of the Shape variant.
        std::vector<size_t> count(std::variant_size_v<Shape>, 0);
        std::vector<const char*> name(count.size(), "");
        for (const Shape& s : scene.shapes) {
            ++count[s.index()];
            name[s.index()] = shape_name(s);
        }
        std::string kinds;
        for (size_t k = 0; k < count.size(); ++k)
            if (count[k]) kinds += (kinds.empty() ? "" : ", ") + std::to_string(count[k]) + " " + name[k];
        std::printf("  shapes               %zu (%s)\n", scene.shapes.size(), kinds.c_str());
        std::printf("  primitives           %zu (ids in file order: triangles and shapes interleaved)\n",
                    scene.primitive_count());
    }
    print_instances(scene);
    if (b.empty()) {
        std::printf("  bounds               empty\n");
    } else {
        const Vec3 e = b.extent();
        std::printf("  bounds min           (%g, %g, %g)\n", double(b.min.x), double(b.min.y), double(b.min.z));
        std::printf("  bounds max           (%g, %g, %g)\n", double(b.max.x), double(b.max.y), double(b.max.z));
        std::printf("  extent               (%g, %g, %g)\n", double(e.x), double(e.y), double(e.z));
    }
    std::printf("  materials            %zu", m.materials.size());
    for (size_t i = 0; i < m.materials.size() && i < 8; ++i)
        std::printf("%s%s", i ? ", " : ": ", m.materials[i].name.empty() ? "(unnamed)" : m.materials[i].name.c_str());
    std::printf("%s\n", m.materials.size() > 8 ? ", ..." : "");
}

void print_accel(const Accel& accel) {
    const AccelStats st = accel.stats();
    std::printf("\nstructure %s\n", accel.spec().c_str());
    std::printf("  primitives           %zu\n", st.primitives);
    std::printf("  nodes                %zu\n", st.nodes);
    std::printf("  leaves               %zu\n", st.leaves);
    std::printf("  max depth            %zu\n", st.max_depth);
    std::printf("  structure memory     %s (%zu bytes", format_bytes(double(st.bytes)).c_str(), st.bytes);
    if (st.primitives) std::printf(", %.1f bytes/primitive", double(st.bytes) / double(st.primitives));
    std::printf(")\n");
    std::printf("  primitive memory     %s\n", format_bytes(double(st.primitive_bytes)).c_str());
    if (st.sah_cost > 0)
        std::printf("  SAH cost             %.3f (C_trav = %g, C_isect = %g)\n", st.sah_cost,
                    double(kSahTraversalCost), double(kSahIntersectionCost));
    else
        std::printf("  SAH cost             undefined for this structure\n");
    std::printf("  build time           %s\n", format_duration(st.build_ms / 1000.0).c_str());
    for (const auto& [key, value] : st.extra) std::printf("  %-20s %s\n", key.c_str(), value.c_str());
}

int run_info(const InfoArgs& args) {
    std::optional<AccelSpec> spec;
    if (!args.no_accel) spec = validate_accel_choice(args.accel);
    const Scene scene = load_scene_verbose(args.scene);
    std::unique_ptr<Accel> accel;
    if (!args.no_accel) accel = make_accel_verbose(args.accel, spec, scene, args.threads);
    print_scene(scene);
    if (accel) print_accel(*accel);
    return 0;
}

}  // namespace

Command add_info_command(CLI::App& app) {
    auto args = std::make_shared<InfoArgs>();
    CLI::App* cmd = app.add_subcommand("info", "print statistics of SCENE and of a structure built over it");
    cmd->footer("Structure figures: nodes and leaves in use, deepest leaf, memory of nodes and index arrays "
                "(primitive storage separate), SAH cost with C_trav = 1 and C_isect = 1 (cost(leaf) = C_isect * "
                "primitives, cost(node) = C_trav + sum of area(child)/area(node) * cost(child)), build time.");
    add_scene_argument(cmd, args->scene);
    add_accel_options(cmd, args->accel);
    cmd->add_flag("--no-accel", args->no_accel, "only describe the scene, build nothing");
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_info(*args); }};
}

Command add_accels_command(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand("accels", "list the acceleration structures, their options and variants");
    return {cmd, [] {
                std::fputs(describe_accels().c_str(), stdout);
                return 0;
            }};
}

}  // namespace thicket::cli
