#pragma once
/// `bvh8:nodes=compressed`: the 8-wide tree's nodes quantized to QNode (node.h), 96 bytes
/// against Node's 256, with conservative rounding so that every decoded box contains the exact
/// one and the kernels' hits are unchanged (docs/bvh8.md, "Compressed nodes").
#include <cstddef>
#include <span>

#include "thicket/bvh8/node.h"
#include "thicket/core/aligned.h"

namespace thicket::bvh8 {

using QNodes = AlignedVector<QNode, 64>;

/// The QNodes of `nodes`, node for node (the same indices, children and leaves): per axis the
/// origin is the smallest valid lower plane and 2^e the smallest power of two (at least 2^-126)
/// that spans the largest upper plane in 255 steps; lower planes round down and upper planes up,
/// each checked against its float. An axis where a valid box has an infinite or NaN plane spans
/// every float instead (origin -FLT_MAX, steps of 2^127 up to +inf): it holds every finite point,
/// which is all a hit can be. Throws Error when a child index or leaf size does not fit the child
/// word (2^kQIndexBits entries, 255 per leaf).
QNodes compress_nodes(std::span<const Node> nodes);

/// The Node whose boxes are q's decoded planes (the floats the kernels test), children and leaf
/// sizes unpacked, empty lanes inverted as the collapse leaves them.
Node decode_node(const QNode& q);

/// Every node decoded (decode_node), then each lane's box grown to enclose its child node's
/// decoded lanes (a child's planes round outward on its own grid, past its parent's): the tree
/// that is saved for a compressed structure, as the load proof wants it (bvh8_io.h).
void decode_nodes(std::span<const QNode> q, AlignedVector<Node, 64>& out);

/// set_plane_bounds over the decoded boxes of nodes[0..count).
void set_plane_bounds(TraceContext& ctx, const QNode* nodes, size_t count);

}  // namespace thicket::bvh8
