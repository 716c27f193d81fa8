#pragma once
/// The uniform grid (Amanatides & Woo 1987) over any primitive set: resolution from the density
/// rule, compact cell lists, 3D-DDA traversal with the hit-inside-cell rule and an optional
/// per-ray mailbox. Usable directly (no virtual call) or through the Accel interface.
#include "thicket/accel/accel.h"
#include "thicket/grid/draw.h"
#include "thicket/grid/grid_build.h"
#include "thicket/grid/grid_io.h"
#include "thicket/grid/grid_stats.h"
#include "thicket/grid/grid_traversal.h"

namespace thicket {

template <PrimitiveSet Prims>
class Grid final : public AccelBase<Grid<Prims>> {
public:
    Grid(Prims prims, const GridOptions& options) : prims_(std::move(prims)), options_(options) {
        data_ = build_grid(prims_, options_);
    }

    /// Adopts a saved grid after proving it answers like the one these options build (adopt_grid).
    Grid(Prims prims, SavedGrid saved, const GridOptions& options) : prims_(std::move(prims)), options_(options) {
        data_ = adopt_grid(prims_, std::move(saved), options_);
    }

    Aabb bounds() const override { return data_.box; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        Hit hit = miss_for(ray);
        grid_walk<false>(data_, prims_, ray, hit, options_.mailbox, counters);
        return hit;
    }
    template <class C>
    bool any(const Ray& ray, C& counters) const {
        Hit unused = miss_for(ray);
        return grid_walk<true>(data_, prims_, ray, unused, options_.mailbox, counters);
    }

    /// Both walks report their steps to a TraversalRecorder (Accel::intersect, occluded).
    static constexpr bool kRecordsSteps = true;
    static constexpr bool kRecordsAnyHitSteps = true;
    AccelStats stats() const override {
        AccelStats s = this->base_stats();
        s.primitives = prims_.size();
        s.primitive_bytes = prims_.bytes();
        s.bytes = data_.lists.bytes();
        if (data_.lists.cells() == 0) return s;
        const CellFigures f = cell_figures(data_.frame, data_.lists, 0, data_.box.area());
        s.nodes = f.cells;
        s.leaves = f.cells - f.empty;
        s.max_depth = 1;
        s.sah_cost = f.cost;
        const GridResolution res{data_.frame.res};
        s.extra.emplace_back("resolution", res.str());
        s.extra.emplace_back("cells", std::to_string(f.cells));
        s.extra.emplace_back("empty cells", std::to_string(f.empty) + " (" + percent(double(f.empty), double(f.cells)) + ")");
        s.extra.emplace_back("references", std::to_string(f.refs));
        s.extra.emplace_back("references per primitive", fixed(double(f.refs) / double(prims_.size()), 2));
        s.extra.emplace_back("largest cell", std::to_string(f.max_refs) + " references");
        return s;
    }

    void save(std::ostream& out) const override { write_grid(out, data_); }

    const GridData& data() const { return data_; }
    const Prims& primitives() const { return prims_; }

private:
    Prims prims_;
    GridOptions options_;
    GridData data_;
};

}  // namespace thicket
