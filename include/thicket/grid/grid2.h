#pragma once
/// The two-level grid (Kalojanov, Billeter & Slusallek 2011) over any primitive set: a coarse
/// uniform grid whose non-empty cells hold their own uniform sub-grid sized by the density rule
/// on the cell's primitive count. Same hit-inside-cell rule and per-ray mailbox as the grid.
#include "thicket/accel/accel.h"
#include "thicket/grid/draw.h"
#include "thicket/grid/grid2_build.h"
#include "thicket/grid/grid2_traversal.h"
#include "thicket/grid/grid_io.h"
#include "thicket/grid/grid_stats.h"

namespace thicket {

template <PrimitiveSet Prims>
class TwoLevelGrid final : public AccelBase<TwoLevelGrid<Prims>> {
public:
    TwoLevelGrid(Prims prims, const Grid2Options& options) : prims_(std::move(prims)), options_(options) {
        data_ = build_grid2(prims_, options_);
    }

    /// Adopts a saved grid after proving it answers like the one these options build (adopt_grid2).
    TwoLevelGrid(Prims prims, SavedGrid2 saved, const Grid2Options& options)
        : prims_(std::move(prims)), options_(options) {
        data_ = adopt_grid2(prims_, std::move(saved), options_);
    }

    Aabb bounds() const override { return data_.box; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        Hit hit = miss_for(ray);
        grid2_walk<false>(data_, prims_, ray, hit, options_.mailbox, counters);
        return hit;
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        Hit unused = miss_for(ray);
        return grid2_walk<true>(data_, prims_, ray, unused, options_.mailbox, counters);
    }

    AccelStats stats() const override {
        AccelStats s = this->base_stats();
        s.primitives = prims_.size();
        s.primitive_bytes = prims_.bytes();
        s.bytes = data_.top.size() * sizeof(TopCell) + data_.leaves.bytes();
        if (data_.top.empty()) return s;
        const Grid2Figures f = grid2_figures(data_);
        s.nodes = f.top_cells + f.leaf.cells;
        s.leaves = f.leaf.cells - f.leaf.empty;
        s.max_depth = 2;
        s.sah_cost = f.cost;
        const GridResolution res{data_.frame.res};
        s.extra.emplace_back("top resolution", res.str());
        s.extra.emplace_back("top cells", std::to_string(f.top_cells) + " (" + std::to_string(f.top_empty) + " empty, " +
                                              percent(double(f.top_empty), double(f.top_cells)) + ")");
        s.extra.emplace_back("top references", std::to_string(data_.top_references));
        s.extra.emplace_back("sub-grid cells", std::to_string(f.leaf.cells) + " (" +
                                                   fixed(double(f.leaf.cells) / double(f.top_cells - f.top_empty), 1) +
                                                   " per non-empty top cell)");
        s.extra.emplace_back("empty sub-grid cells",
                             std::to_string(f.leaf.empty) + " (" + percent(double(f.leaf.empty), double(f.leaf.cells)) + ")");
        s.extra.emplace_back("references", std::to_string(f.leaf.refs));
        s.extra.emplace_back("references per primitive", fixed(double(f.leaf.refs) / double(prims_.size()), 2));
        s.extra.emplace_back("largest cell", std::to_string(f.leaf.max_refs) + " references");
        return s;
    }

    void save(std::ostream& out) const override { write_grid2(out, data_); }

    const Grid2Data& data() const { return data_; }
    const Prims& primitives() const { return prims_; }

private:
    Prims prims_;
    Grid2Options options_;
    Grid2Data data_;
};

}  // namespace thicket
