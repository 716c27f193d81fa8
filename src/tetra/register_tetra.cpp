#include "accel/dispatch.h"
#include "thicket/tetra/tetra.h"

namespace thicket {

namespace {

constexpr Choice<bool> kSurface[] = {{"refine", false}, {"preserve", true}};

/// The build options a parsed spec asks for.
TetraBuildOptions build_options(const AccelSpec& spec) {
    TetraBuildOptions o;
    o.time_limit_s = double(spec.get_int("time-limit"));
    o.memory_limit_mb = size_t(spec.get_int("memory-limit"));
    o.max_triangles = size_t(spec.get_int("max-triangles"));
    o.preserve_surface = spec.choice("surface", kSurface);
    o.threads = spec.threads;
    return o;
}

}  // namespace

void register_tetra(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "tetra";
    info.partitioning = Partitioning::Space;
    info.summary = "constrained tetrahedralization (Lagae & Dutre 2008) by TetGen, walked tetrahedron to "
                   "tetrahedron; meshes triangles only: shapes and triangles TetGen refuses go to a fallback bvh";
    info.options = {
        {"max-triangles", "scenes with more triangles are not handed to TetGen (all go to the fallback bvh)", "200000",
         {}, 0, 100000000},
        {"time-limit", "seconds each TetGen run may take before it is stopped (then: fallback bvh)", "60", {}, 1, 86400},
        {"memory-limit", "MiB of address space the TetGen process may use", "4096", {}, 64, 1 << 20},
        choice_option("surface",
                      "refine: TetGen may split triangles with Steiner points to recover them; preserve (-Y): "
                      "it may not (Steiner points go inside the volume)",
                      false, kSurface),
    };
    // One variant, capped at 20,000 triangles: TetGen takes seconds on the nasty scenes and tens
    // of seconds on Sponza or Sibenik, the suite's budget is a few; the larger shared scenes go
    // to the fallback bvh here, with the reason printed (docs/tetra.md has their figures).
    info.variants = {"tetra:max-triangles=20000"};
    set_build_and_load<Tetra>(info, build_options, read_tetra);
    registry.push_back(std::move(info));
}

}  // namespace thicket
