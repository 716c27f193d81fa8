#include "accel/dispatch.h"
#include "thicket/tetra/tetra.h"

namespace thicket {

namespace {

constexpr Choice<bool> kSurface[] = {{"refine", false}, {"preserve", true}};

}  // namespace

void register_tetra(std::vector<AccelInfo>& registry) {
    using O = TetraBuildOptions;
    const OptionFields<O> fields = {
        int_field("max-triangles", "scenes with more triangles are not handed to TetGen (all go to the fallback bvh)",
                  &O::max_triangles, 0, 100000000),
        int_field("time-limit", "seconds each TetGen run may take before it is stopped (then: fallback bvh)",
                  &O::time_limit_s, 1, 86400),
        int_field("memory-limit", "MiB of address space the TetGen process may use", &O::memory_limit_mb, 64, 1 << 20),
        choice_field("surface",
                     "refine: TetGen may split triangles with Steiner points to recover them; preserve (-Y): "
                     "it may not (Steiner points go inside the volume)",
                     &O::preserve_surface, kSurface),
        threads_field(&O::threads),
    };
    // One variant, capped at 20,000 triangles: TetGen takes seconds on the nasty scenes and tens
    // of seconds on Sponza or Sibenik, the suite's budget is a few; the larger shared scenes go
    // to the fallback bvh here, with the reason printed (docs/tetra.md has their figures).
    AccelInfo info = accel_info({.name = "tetra",
                                 .partitioning = Partitioning::Space,
                                 .summary = "constrained tetrahedralization (Lagae & Dutre 2008) by TetGen, walked "
                                            "tetrahedron to tetrahedron; meshes triangles only: shapes and triangles "
                                            "TetGen refuses go to a fallback bvh",
                                 .variants = {"tetra:max-triangles=20000"}},
                                fields);
    set_build_and_load<Tetra>(info, fields, read_tetra);
    registry.push_back(std::move(info));
}

}  // namespace thicket
