// Registration of the uniform grid and the two-level grid: spec options and tested variants.
#include "accel/dispatch.h"
#include "thicket/grid/grid.h"
#include "thicket/grid/grid2.h"

namespace thicket {

namespace {

constexpr Choice<bool> kMailbox[] = {{"on", true}, {"off", false}};
constexpr Choice<GridAssign> kAssign[] = {{"clip", GridAssign::Clip}, {"bounds", GridAssign::Bounds}};

/// The options both grids take: `mailbox` and `assign`.
template <class Options>
OptionFields<Options> cell_list_fields() {
    return {choice_field("mailbox",
                         "per-ray mailbox: each primitive is tested once per ray even when several cells reference "
                         "it (off: re-tested in every cell, to show the effect)",
                         &Options::mailbox, kMailbox),
            choice_field("assign",
                         "which cells a primitive goes into: those it really overlaps (exact clipping for triangles "
                         "and for primitives with a clip hook; others fall back to their bounds), or every cell its "
                         "bounding box overlaps",
                         &Options::assign, kAssign)};
}

/// A density option written in sixteenths of a cell per primitive, stored as cells per primitive.
OptionField<Grid2Options> sixteenths_field(std::string key, std::string help, double Grid2Options::*member) {
    OptionField<Grid2Options> f = custom_field<Grid2Options>(
        OptionInfo{key, std::move(help), {}, {}, 1, 1024},
        [key, member](const AccelSpec& spec, Grid2Options& o) { o.*member = double(spec.get_int(key)) / 16.0; });
    f.default_of = [member](const Grid2Options& o) { return std::to_string(long(o.*member * 16.0)); };
    return f;
}

}  // namespace

void register_grid(std::vector<AccelInfo>& registry) {
    const OptionFields<GridOptions> fields = join_fields(
        OptionFields<GridOptions>{
            int_field("lambda",
                      "cells per primitive for the automatic resolution: lambda*N cells shaped like the scene's box",
                      &GridOptions::lambda, 1, 64),
            int_field("res", "cells along the longest axis (others proportional); 0: automatic from lambda",
                      &GridOptions::res, 0, 4096)},
        cell_list_fields<GridOptions>());
    AccelInfo info = accel_info(
        {.name = "grid",
         .partitioning = Partitioning::Space,
         .summary = "uniform grid with 3D-DDA (Amanatides & Woo 1987), lambda*N cells, compact cell lists",
         .variants = {"grid", "grid:assign=bounds", "grid:mailbox=off", "grid:lambda=1", "grid:lambda=16",
                      "grid:res=48", "grid:isect=watertight"}},
        fields);
    set_build_and_load<Grid>(info, fields, read_grid);
    registry.push_back(std::move(info));
}

void register_grid2(std::vector<AccelInfo>& registry) {
    const OptionFields<Grid2Options> fields = join_fields(
        OptionFields<Grid2Options>{
            sixteenths_field("top", "top-level density in sixteenths of a cell per primitive (4: N/4 top cells)",
                             &Grid2Options::top_density),
            sixteenths_field("leaf",
                             "sub-grid density in sixteenths of a cell per primitive of its top cell (20: 1.25 "
                             "cells each)",
                             &Grid2Options::leaf_density)},
        cell_list_fields<Grid2Options>());
    AccelInfo info = accel_info({.name = "grid2",
                                 .partitioning = Partitioning::Space,
                                 .summary = "two-level grid (Kalojanov, Billeter & Slusallek 2011): a sub-grid in "
                                            "every non-empty top cell",
                                 .variants = {"grid2", "grid2:assign=bounds", "grid2:mailbox=off",
                                              "grid2:top=1,leaf=80", "grid2:isect=watertight"}},
                                fields);
    set_build_and_load<TwoLevelGrid>(info, fields, read_grid2);
    registry.push_back(std::move(info));
}

}  // namespace thicket
