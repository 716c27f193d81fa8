// Registration of the uniform grid and the two-level grid: spec options and tested variants.
#include "accel/dispatch.h"
#include "thicket/grid/grid.h"
#include "thicket/grid/grid2.h"

namespace thicket {

namespace {

constexpr Choice<bool> kMailbox[] = {{"on", true}, {"off", false}};
constexpr Choice<GridAssign> kAssign[] = {{"clip", GridAssign::Clip}, {"bounds", GridAssign::Bounds}};

OptionInfo mailbox_option() {
    return choice_option("mailbox",
                         "per-ray mailbox: each primitive is tested once per ray even when several cells reference "
                         "it (off: re-tested in every cell, to show the effect)",
                         true, kMailbox);
}

OptionInfo assign_option() {
    return choice_option("assign",
                         "which cells a primitive goes into: those it really overlaps (exact clipping for triangles "
                         "and for primitives with a clip hook; others fall back to their bounds), or every cell its "
                         "bounding box overlaps",
                         GridAssign::Clip, kAssign);
}

GridAssign assign_of(const AccelSpec& spec) { return spec.choice("assign", kAssign); }

GridOptions grid_options(const AccelSpec& spec) {
    GridOptions o;
    o.lambda = double(spec.get_int("lambda"));
    o.res = uint32_t(spec.get_int("res"));
    o.mailbox = spec.choice("mailbox", kMailbox);
    o.assign = assign_of(spec);
    return o;
}

Grid2Options grid2_options(const AccelSpec& spec) {
    Grid2Options o;
    o.top_density = double(spec.get_int("top")) / 16.0;
    o.leaf_density = double(spec.get_int("leaf")) / 16.0;
    o.mailbox = spec.choice("mailbox", kMailbox);
    o.assign = assign_of(spec);
    return o;
}

}  // namespace

void register_grid(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "grid";
    info.partitioning = Partitioning::Space;
    info.summary = "uniform grid with 3D-DDA (Amanatides & Woo 1987), lambda*N cells, compact cell lists";
    info.options = {
        {"lambda", "cells per primitive for the automatic resolution: lambda*N cells shaped like the scene's box",
         "5", {}, 1, 64},
        {"res", "cells along the longest axis (others proportional); 0: automatic from lambda", "0", {}, 0, 4096},
        mailbox_option(),
        assign_option(),
    };
    info.variants = {
        "grid",
        "grid:assign=bounds",
        "grid:mailbox=off",
        "grid:lambda=1",
        "grid:lambda=16",
        "grid:res=48",
        "grid:isect=watertight",
    };
    info.build = [](const Scene& scene, const AccelSpec& spec) {
        return make_structure<Grid>(scene, spec, grid_options(spec));
    };
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        return make_structure<Grid>(scene, spec, read_grid(in, scene.primitive_count()), grid_options(spec));
    };
    registry.push_back(std::move(info));
}

void register_grid2(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "grid2";
    info.partitioning = Partitioning::Space;
    info.summary = "two-level grid (Kalojanov, Billeter & Slusallek 2011): a sub-grid in every non-empty top cell";
    info.options = {
        {"top", "top-level density in sixteenths of a cell per primitive (4: N/4 top cells)", "4", {}, 1, 1024},
        {"leaf", "sub-grid density in sixteenths of a cell per primitive of its top cell (20: 1.25 cells each)", "20",
         {}, 1, 1024},
        mailbox_option(),
        assign_option(),
    };
    info.variants = {
        "grid2",
        "grid2:assign=bounds",
        "grid2:mailbox=off",
        "grid2:top=1,leaf=80",
        "grid2:isect=watertight",
    };
    info.build = [](const Scene& scene, const AccelSpec& spec) {
        return make_structure<TwoLevelGrid>(scene, spec, grid2_options(spec));
    };
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        return make_structure<TwoLevelGrid>(scene, spec, read_grid2(in, scene.primitive_count()),
                                            grid2_options(spec));
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
