// Saved structures whose bytes were changed after saving (issue 16): the spec is inside the
// checksum, and a payload changed with its checksum recomputed to match (as a careless tool or a
// fuzzer would) is either refused by the structure's validator or answers every ray like brute
// force. The validators must prove what traversal relies on, not only that the file is well formed.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <sstream>
#include <string>

#include "saved_bytes.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh/bvh.h"
#include "thicket/bvh8/node.h"
#include "thicket/grid/grid.h"
#include "thicket/grid/grid2.h"
#include "thicket/octree/octree.h"
#include "thicket/prims/triangles.h"
#include "thicket/core/error.h"

namespace thicket::saved_payload_test {
namespace {

using testing::error_of;
using testing::layout_of;
using testing::reseal;
using testing::with_payload;

TEST(SavedStructure, TheSpecTextIsInsideTheChecksum) {
    const Scene scene = load_scene("cornell");
    const std::string bytes = saved_accel_bytes(*build_accel("bvh:max-leaf=8", scene), scene);
    std::string edited = bytes;
    const size_t at = edited.find("max-leaf=8");
    ASSERT_NE(at, std::string::npos);
    edited[at + 9] = '1';
    EXPECT_NE(error_of(edited, scene).find("checksum"), std::string::npos) << error_of(edited, scene);
    EXPECT_EQ(error_of(bytes, scene), "");
    EXPECT_EQ(load_accel_bytes(bytes, scene, "x")->spec(), parse_accel_spec("bvh:max-leaf=8").str());
}

// Every byte of each loadable structure's payload gets one bit flipped (bit i mod 8 of byte i),
// the checksum recomputed: the result must be refused or agree with brute force on every ray.
// The BSP is not in the list: its validator proves only structure so far (a flipped plane bit
// loads and answers wrongly; docs/fuzzing.md), and the BSP's entry below shows it.
TEST(SavedStructure, AFlippedPayloadBitIsRefusedOrHarmless) {
    const Scene scene = load_scene("cornell");
    const std::vector<Ray> rays = testing::conformance_rays(scene, 300, 16);
    const auto brute = build_accel("brute", scene);
    std::vector<Hit> truth;
    for (const Ray& r : rays) truth.push_back(brute->intersect(r));
    // bvh:builder=sbvh: leaves holding clipped parts of triangles, whose coverage the validator proves.
    for (const char* spec : {"bvh", "bvh:traversal=ordered-axis", "bvh:builder=sbvh,alpha=0,budget=1,max-leaf=2", "kdtree",
                             "kdtree:builder=median", "bih", "bvh8", "bvh8:leaf-merge=8", "grid", "grid:assign=bounds", "grid2", "octree",
                             "octree:traversal=restart", "obb", "obb:fit=axes", "tetra"}) {
        const std::string bytes = saved_accel_bytes(*build_accel(spec, scene), scene);
        const size_t payload_at = layout_of(bytes).payload_at;
        size_t refused = 0, loaded = 0;
        for (size_t i = payload_at; i < bytes.size(); ++i) {
            std::string flipped = bytes;
            flipped[i] = char(flipped[i] ^ (1 << (i % 8)));
            std::unique_ptr<Accel> accel;
            try {
                accel = load_accel_bytes(reseal(flipped), scene, "flipped");
            } catch (const Error&) {
                ++refused;
                continue;
            }
            ++loaded;
            for (size_t k = 0; k < rays.size(); ++k) {
                const Hit h = accel->intersect(rays[k]);
                ASSERT_EQ(h.found(), truth[k].found())
                    << spec << ": byte " << i - payload_at << " flipped, ray " << k << " loaded but answers wrongly";
                if (h.found()) {
                    ASSERT_LE(std::fabs(h.t - truth[k].t), 1e-5f * truth[k].t)
                        << spec << ": byte " << i - payload_at << " flipped, ray " << k;
                }
                ASSERT_EQ(accel->occluded(rays[k]), truth[k].found()) << spec << ": byte " << i - payload_at;
            }
        }
        EXPECT_GT(refused, 0u) << spec;
        RecordProperty(std::string(spec) + "_loaded", int(loaded));
    }
}

/// Loading a bvh8 proves more than its structure: each change below keeps the file well formed
/// (checksum resealed) and must be refused by name.
TEST(SavedStructure, Bvh8RefusesShrunkBoxesForeignTrianglesAndFilledEmptyLanes) {
    const Scene scene = load_scene("cornell");
    const std::string bytes = saved_accel_bytes(*build_accel("bvh8", scene), scene);
    const size_t payload = layout_of(bytes).payload_at;
    uint64_t nodes = 0, blocks = 0;
    std::memcpy(&nodes, bytes.data() + payload, 8);
    std::memcpy(&blocks, bytes.data() + payload + 8, 8);
    ASSERT_GE(nodes, 1u);
    ASSERT_GE(blocks, 1u);
    const size_t node0 = payload + 24, block0 = node0 + nodes * sizeof(bvh8::Node);
    ASSERT_EQ(error_of(bytes, scene), "");

    auto edited = [&](size_t at, float value) {
        std::string b = bytes;
        std::memcpy(b.data() + at, &value, 4);
        return reseal(b);
    };
    // The root's first valid lane: its upper x moved below its lower x, so that its box no longer
    // holds what it did (the Cornell box's lanes may be flat).
    bvh8::Node root;
    std::memcpy(&root, bytes.data() + node0, sizeof root);
    const int lane = std::countr_zero(root.valid);
    const float lo = root.box[0][0][lane];
    const size_t upper_x = node0 + offsetof(bvh8::Node, box) + (1 * bvh8::kWidth + size_t(lane)) * 4;
    const std::string shrunk = error_of(edited(upper_x, lo - 1.0f - std::fabs(lo)), scene);
    EXPECT_NE(shrunk.find("does not enclose"), std::string::npos) << shrunk;

    // A vertex of the first block's first lane moved by one ulp.
    bvh8::Tri4 block;
    std::memcpy(&block, bytes.data() + block0, sizeof block);
    ASSERT_NE(block.id[0], kNoPrim);
    const float x = block.v[0][0][0];
    EXPECT_NE(error_of(edited(block0, std::nextafter(x, INFINITY)), scene).find("differs from the scene"),
              std::string::npos);

    // The first block's first lane renamed empty while it keeps its vertices.
    std::string renamed = bytes;
    const uint32_t none = kNoPrim;
    std::memcpy(renamed.data() + block0 + offsetof(bvh8::Tri4, id), &none, 4);
    EXPECT_NE(error_of(reseal(renamed), scene).find("empty lane with a vertex"), std::string::npos)
        << error_of(reseal(renamed), scene);
}

// Found by the fuzz.saved replay (the input is fuzz/regressions/saved/bvh-leaves-overlap.bin,
// which fuzz.saved replays): a leaf whose first entry was changed to another leaf's still covered
// n entries in total, fit its box, and loaded; two triangles became unreachable.
TEST(SavedStructure, BvhLeavesThatShareEntriesAreRefused) {
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("bvh:max-leaf=2", scene);
    BvhData data = dynamic_cast<const Bvh<Triangles<>>&>(*accel).data();
    std::vector<uint32_t> leaves;
    for (uint32_t i = 0; i < data.nodes_used; ++i)
        if (i != 1 && data.nodes[i].is_leaf() && data.nodes[i].count == 2) leaves.push_back(i);
    ASSERT_GE(leaves.size(), 2u);
    data.nodes[leaves[1]].leftFirst = data.nodes[leaves[0]].leftFirst;
    try {
        validate_bvh(data, scene.primitive_count());
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("leaves overlap"), std::string::npos) << e.what();
    }
}

/// Takes the first entry out of the first non-empty cell of `lists`, keeping the offsets and the
/// single-cell marks consistent; returns that cell.
size_t drop_first_entry(CellLists& lists, size_t primitive_count) {
    size_t cell = 0;
    while (lists.count(cell) == 0) ++cell;
    lists.refs.erase(lists.refs.begin() + lists.start[cell]);
    for (size_t c = cell + 1; c < lists.start.size(); ++c) --lists.start[c];
    for (uint32_t& r : lists.refs) r &= kPrimMask;
    mark_single_cell_references(lists.refs, primitive_count);
    return cell;
}

// A grid proves on loading that every cell lists every primitive the builder puts in it: a
// payload with one entry taken out (offsets and single-cell marks kept consistent, checksum
// resealed) is refused, so is one cut short, and so is a resolution other than the spec's.
TEST(SavedStructure, GridsMissingAnEntryOrOfAnotherResolutionAreRefused) {
    const Scene scene = load_scene("cornell");
    for (const char* spec : {"grid", "grid:assign=bounds"}) {
        const auto accel = build_accel(spec, scene);
        const std::string bytes = saved_accel_bytes(*accel, scene);
        ASSERT_EQ(error_of(bytes, scene), "") << spec;
        GridData data = dynamic_cast<const Grid<Triangles<>>&>(*accel).data();
        std::ostringstream whole;
        write_grid(whole, data);
        EXPECT_EQ(bytes.substr(layout_of(bytes).payload_at), whole.str());

        const size_t cell = drop_first_entry(data.lists, scene.primitive_count());
        std::ostringstream shrunk;
        write_grid(shrunk, data);
        const std::string missing = error_of(with_payload(bytes, shrunk.str()), scene);
        EXPECT_NE(missing.find("saved.bin: invalid grid: cell " + std::to_string(cell) + " does not list primitive"),
                  std::string::npos)
            << spec << ": " << missing;

        const std::string cut = error_of(with_payload(bytes, whole.str().substr(0, whole.str().size() - 4)), scene);
        EXPECT_NE(cut.find("grid payload truncated in cell entries"), std::string::npos) << cut;
    }
    const std::string coarse = saved_accel_bytes(*build_accel("grid:lambda=1", scene), scene);
    const std::string fine = saved_accel_bytes(*build_accel("grid", scene), scene);
    const std::string other = error_of(with_payload(fine, coarse.substr(layout_of(coarse).payload_at)), scene);
    EXPECT_NE(other.find("where the spec's options give"), std::string::npos) << other;

    const Scene empty;
    const std::string nothing = saved_accel_bytes(*build_accel("grid", empty), empty);
    EXPECT_EQ(error_of(nothing, empty), "");
}

// The two-level grid likewise: its sub-grids' cells must list every primitive the builder puts in
// them, and every top cell's sub-grid must have the builder's resolution.
TEST(SavedStructure, TwoLevelGridsMissingAnEntryOrOfAnotherSubGridAreRefused) {
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("grid2", scene);
    const std::string bytes = saved_accel_bytes(*accel, scene);
    ASSERT_EQ(error_of(bytes, scene), "");
    Grid2Data data = dynamic_cast<const TwoLevelGrid<Triangles<>>&>(*accel).data();
    std::ostringstream whole;
    write_grid2(whole, data);
    EXPECT_EQ(bytes.substr(layout_of(bytes).payload_at), whole.str());

    const size_t cell = drop_first_entry(data.leaves, scene.primitive_count());
    std::ostringstream shrunk;
    write_grid2(shrunk, data);
    const std::string missing = error_of(with_payload(bytes, shrunk.str()), scene);
    EXPECT_NE(missing.find("saved.bin: invalid grid2: cell " + std::to_string(cell) + " does not list primitive"),
              std::string::npos)
        << missing;

    const std::string cut = error_of(with_payload(bytes, whole.str().substr(0, whole.str().size() - 4)), scene);
    EXPECT_NE(cut.find("grid2 payload truncated in cell entries"), std::string::npos) << cut;

    const std::string finer = saved_accel_bytes(*build_accel("grid2:leaf=80", scene), scene);
    const std::string other = error_of(with_payload(bytes, finer.substr(layout_of(finer).payload_at)), scene);
    EXPECT_NE(other.find("sub-grid, where the builder makes"), std::string::npos) << other;

    const Scene empty;
    EXPECT_EQ(error_of(saved_accel_bytes(*build_accel("grid2", empty), empty), empty), "");
}

// An octree proves on loading that every leaf lists every primitive whose part reaches its cell:
// a leaf with one entry taken out (the other leaves' ranges kept consistent, checksum resealed) is
// refused, so is a payload cut short, and so is a moved root cell.
TEST(SavedStructure, OctreesMissingAnEntryOrWithAnotherRootAreRefused) {
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("octree:leaf-size=2", scene);
    const std::string bytes = saved_accel_bytes(*accel, scene);
    ASSERT_EQ(error_of(bytes, scene), "");
    const OctreeData& built = dynamic_cast<const Octree<Triangles<>>&>(*accel).data();
    auto saved_with = [&](const OctreeData& data) {
        std::ostringstream out;
        write_octree(out, data);
        return with_payload(bytes, out.str());
    };
    EXPECT_EQ(saved_with(built), bytes);

    OctreeData data = built;
    uint32_t leaf = 0;
    while (!data.nodes[leaf].is_leaf() || data.nodes[leaf].count == 0) ++leaf;
    const uint32_t at = data.nodes[leaf].index;
    data.refs.erase(data.refs.begin() + at);
    --data.nodes[leaf].count;
    for (OctreeNode& n : data.nodes)
        if (n.is_leaf() && n.index > at) --n.index;
    const std::string missing = error_of(saved_with(data), scene);
    EXPECT_NE(missing.find("saved.bin: invalid octree: leaf " + std::to_string(leaf) + " does not list primitive"),
              std::string::npos)
        << missing;

    const std::string payload = bytes.substr(layout_of(bytes).payload_at);
    const std::string cut = error_of(with_payload(bytes, payload.substr(0, payload.size() - 4)), scene);
    EXPECT_NE(cut.find("octree payload truncated in references"), std::string::npos) << cut;

    data = built;
    data.root.max.x += 1.0f;
    EXPECT_NE(error_of(saved_with(data), scene).find("root cell"), std::string::npos);

    const Scene empty;
    EXPECT_EQ(error_of(saved_accel_bytes(*build_accel("octree", empty), empty), empty), "");
}

// The BSP's proof is a rebuild (prove_bsp_rebuilt): a plane offset changed with the checksum
// resealed passes its structural validator but not the comparison; its own file loads.
TEST(SavedStructure, ABspWithAMovedPlaneIsRefused) {
    const Scene scene = load_scene("cornell");
    const std::string bytes = saved_accel_bytes(*build_accel("bsp", scene), scene);
    EXPECT_EQ(error_of(bytes, scene), "");
    std::string flipped = bytes;
    const size_t at = layout_of(bytes).payload_at + 20;
    flipped[at] = char(flipped[at] ^ (1 << (at % 8)));
    const std::string why = error_of(reseal(flipped), scene);
    EXPECT_NE(why.find("not the tree this scene and spec build"), std::string::npos) << why;
}

}  // namespace
}  // namespace thicket::saved_payload_test
