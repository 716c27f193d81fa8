// Refit of the 8-wide tree: new vertices into the existing blocks, then every box again. The
// leaf lanes (nearly all the work) are independent and go in parallel; the interior lanes follow
// in one backward sweep, each reading a child node already done.
#include "thicket/bvh8/refit.h"

#include <algorithm>
#include <cstdint>

#include "thicket/core/ray.h"
#include "thicket/core/sah.h"
#include "thicket/prims/triangles.h"
#include "thicket/util/parallel.h"

namespace thicket::bvh8 {

namespace {

Aabb lane_box(const Node& node, int lane) {
    Aabb b;
    for (int a = 0; a < 3; ++a) {
        b.min[a] = node.box[a][0][lane];
        b.max[a] = node.box[a][1][lane];
    }
    return b;
}

void set_lane_box(Node& node, int lane, const Aabb& b) {
    for (int a = 0; a < 3; ++a) {
        node.box[a][0][lane] = b.min[a];
        node.box[a][1][lane] = b.max[a];
    }
}

Aabb node_box(const Node& node) {
    Aabb b;
    for (int lane = 0; lane < kWidth; ++lane)
        if ((node.valid >> lane) & 1u) b.grow(lane_box(node, lane));
    return b;
}

/// The box of the filled lanes of blocks [first, first + size).
Aabb blocks_box(const Blocks& blocks, uint32_t first, uint32_t size) {
    Aabb b;
    for (uint32_t k = first; k < first + size; ++k)
        for (int lane = 0; lane < 4; ++lane) {
            if (blocks[k].id[lane] == kNoPrim) continue;
            for (int v = 0; v < 3; ++v)
                b.grow(Vec3(blocks[k].v[v][0][lane], blocks[k].v[v][1][lane], blocks[k].v[v][2][lane]));
        }
    return b;
}

uint32_t blocks_count(const Blocks& blocks, uint32_t first, uint32_t size) {
    uint32_t n = 0;
    for (uint32_t k = first; k < first + size; ++k)
        for (int lane = 0; lane < 4; ++lane) n += blocks[k].id[lane] != kNoPrim ? 1 : 0;
    return n;
}

template <class Tris>
void repack(Blocks& blocks, const Tris& tris, unsigned threads) {
    parallel_for(blocks.size(), 1024, threads, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
            Tri4& b = blocks[k];
            for (int lane = 0; lane < 4; ++lane) {
                if (b.id[lane] == kNoPrim) continue;  // unused lanes stay all-zero
                const auto v = tris.triangle(b.id[lane]);
                for (int vertex = 0; vertex < 3; ++vertex)
                    for (int a = 0; a < 3; ++a) b.v[vertex][a][lane] = v[size_t(vertex)][a];
            }
        }
    });
}

}  // namespace

void refit_tree(Tree& tree, const LeafBox& leaf_box, const LeafCount& leaf_count, unsigned threads) {
    auto& nodes = tree.nodes;
    parallel_for(nodes.size(), 256, threads, [&](size_t begin, size_t end) {
        for (size_t n = begin; n < end; ++n)
            for (int lane = 0; lane < kWidth; ++lane)
                if (((nodes[n].valid >> lane) & 1u) && nodes[n].leaf_size[lane] != 0)
                    set_lane_box(nodes[n], lane, leaf_box(nodes[n].child[lane], nodes[n].leaf_size[lane]));
    });
    for (size_t n = nodes.size(); n-- > 0;)
        for (int lane = 0; lane < kWidth; ++lane)
            if (((nodes[n].valid >> lane) & 1u) && nodes[n].leaf_size[lane] == 0)
                set_lane_box(nodes[n], lane, node_box(nodes[nodes[n].child[lane]]));

    // The build's figures (collapse.cpp), with each leaf's count as the lanes now hold it.
    tree.bounds = nodes.empty() ? Aabb() : node_box(nodes[0]);
    const double root_area = tree.bounds.area();
    tree.sah_cost = tree.embree_sah_cost = 0.0;
    if (!(root_area > 0.0)) return;
    for (const Node& node : nodes) {
        const double node_ratio = double(node_box(node).area()) / root_area;
        tree.sah_cost += kSahTraversalCost * node_ratio;
        tree.embree_sah_cost += node_ratio;
        for (int lane = 0; lane < kWidth; ++lane) {
            if (!((node.valid >> lane) & 1u) || node.leaf_size[lane] == 0) continue;
            const uint32_t count = leaf_count(node.child[lane], node.leaf_size[lane]);
            const double ratio = double(lane_box(node, lane).area()) / root_area;
            tree.sah_cost += kSahIntersectionCost * ratio * count;
            tree.embree_sah_cost += ratio * double((count + 3) / 4);
        }
    }
}

template <class Tris>
void refit_blocks(Tree& tree, Blocks& blocks, const Tris& tris, unsigned threads) {
    repack(blocks, tris, threads);
    refit_tree(
        tree, [&](uint32_t first, uint32_t size) { return blocks_box(blocks, first, size); },
        [&](uint32_t first, uint32_t size) { return blocks_count(blocks, first, size); }, threads);
}

template void refit_blocks(Tree&, Blocks&, const Triangles<TriangleTest::Moller>&, unsigned);
template void refit_blocks(Tree&, Blocks&, const Triangles<TriangleTest::Watertight>&, unsigned);

}  // namespace thicket::bvh8
