// Quantizing the 8-wide tree's nodes (nodes=compressed) and decoding them back, in baseline code.
#include "thicket/bvh8/compress.h"

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <string>

#include "thicket/core/error.h"

namespace thicket::bvh8 {

namespace {

constexpr int kMinExponent = -126;  // 2^e stays a normal float, and q * 2^e exact
constexpr int kMaxExponent = 127;
constexpr uint32_t kMaxIndex = (1u << kQIndexBits) - 1u;
constexpr uint32_t kMaxLeafSize = 0xFFu;

float exp2_float(int e) { return std::ldexp(1.0f, e); }

/// The decoded plane, as the kernels compute it: the product is exact, so one rounding.
float decode_plane(float origin, int e, uint32_t q) { return origin + float(q) * exp2_float(e); }

/// Quantizes axis a of `node` into `out` with exponent e; false if an upper plane needs more
/// than 255 steps (the caller tries e + 1).
bool quantize_axis(const Node& node, int a, float origin, int e, QNode& out) {
    const double step = std::ldexp(1.0, e);
    for (int lane = 0; lane < kWidth; ++lane) {
        if (!((node.valid >> lane) & 1u)) {
            out.q[a][0][lane] = 0xFF;  // inverted: the valid mask excludes it anyway
            out.q[a][1][lane] = 0;
            continue;
        }
        const float lo = node.box[a][0][lane], hi = node.box[a][1][lane];
        if (!std::isfinite(lo) || !std::isfinite(hi)) {
            // Only on an unbounded axis (compress_node): the lowest and the highest step, -FLT_MAX
            // and +inf, hold every finite point, which is all a hit can be.
            out.q[a][0][lane] = 0;
            out.q[a][1][lane] = 0xFF;
            if (std::isfinite(lo)) {
                uint32_t l = 0;
                while (l < 255 && decode_plane(origin, e, l + 1) <= lo) ++l;
                out.q[a][0][lane] = uint8_t(l);
            }
            if (std::isfinite(hi)) {
                uint32_t h = 0;
                while (decode_plane(origin, e, h) < hi) ++h;  // ends: step 255 decodes to +inf
                out.q[a][1][lane] = uint8_t(h);
            }
            continue;
        }
        // The estimate in double, then moved until its float decoding is on the right side:
        // decoding is monotone in q, and q = 0 decodes to the origin, the smallest lower plane.
        double ql = std::floor((double(lo) - double(origin)) / step);
        double qh = std::ceil((double(hi) - double(origin)) / step);
        ql = ql < 0.0 ? 0.0 : (ql > 255.0 ? 255.0 : ql);
        qh = qh < 0.0 ? 0.0 : qh;
        if (qh > 255.0) return false;
        uint32_t l = uint32_t(ql), h = uint32_t(qh);
        while (l > 0 && decode_plane(origin, e, l) > lo) --l;
        while (decode_plane(origin, e, h) < hi) {
            if (h == 255) return false;
            ++h;
        }
        out.q[a][0][lane] = uint8_t(l);
        out.q[a][1][lane] = uint8_t(h);
    }
    return true;
}

QNode compress_node(const Node& node, size_t index) {
    QNode out{};
    out.valid = uint8_t(node.valid & 0xFFu);
    for (int a = 0; a < 3; ++a) {
        float lo = INFINITY, hi = -INFINITY;
        bool finite = true;
        for (int lane = 0; lane < kWidth; ++lane) {
            if (!((node.valid >> lane) & 1u)) continue;
            const float l = node.box[a][0][lane], h = node.box[a][1][lane];
            finite = finite && std::isfinite(l) && std::isfinite(h);
            lo = l < lo ? l : lo;
            hi = h > hi ? h : hi;
        }
        if (node.valid == 0) lo = hi = 0.0f;
        if (!finite) {
            // A box with an infinite or NaN plane (a primitive with such vertices, never hit at an
            // infinite point): the axis spans every float in 2^127 steps, -FLT_MAX up to +inf.
            out.origin[a] = -FLT_MAX;
            out.exponent[a] = int8_t(kMaxExponent);
            quantize_axis(node, a, -FLT_MAX, kMaxExponent, out);
            continue;
        }
        // The smallest e with 255 steps spanning [lo, hi], from frexp's estimate.
        const double extent = double(hi) - double(lo);
        int e = kMinExponent;
        if (extent > 0.0) {
            int exp2 = 0;
            std::frexp(extent / 255.0, &exp2);  // extent / 255 < 2^exp2
            e = exp2 - 1 < kMinExponent ? kMinExponent : exp2 - 1;
        }
        while (!quantize_axis(node, a, lo, e, out)) {
            if (++e > kMaxExponent)
                throw Error("bvh8: nodes=compressed cannot quantize node " + std::to_string(index) +
                            " (axis " + std::to_string(a) + ")");
        }
        out.origin[a] = lo;
        out.exponent[a] = int8_t(e);
    }
    for (int lane = 0; lane < kWidth; ++lane) {
        if (!((node.valid >> lane) & 1u)) {
            out.child[lane] = 0;
            continue;
        }
        if (node.child[lane] > kMaxIndex || node.leaf_size[lane] > kMaxLeafSize)
            throw Error("bvh8: nodes=compressed holds at most " + std::to_string(kMaxIndex + 1) +
                        " nodes, blocks or ids and " + std::to_string(kMaxLeafSize) + " per leaf; node " +
                        std::to_string(index) + " lane " + std::to_string(lane) + " has child " +
                        std::to_string(node.child[lane]) + ", leaf size " + std::to_string(node.leaf_size[lane]) +
                        " (use nodes=full)");
        out.child[lane] = node.child[lane] | uint32_t(node.leaf_size[lane]) << kQIndexBits;
    }
    return out;
}

}  // namespace

QNodes compress_nodes(std::span<const Node> nodes) {
    QNodes out(nodes.size());
    for (size_t k = 0; k < nodes.size(); ++k) out[k] = compress_node(nodes[k], k);
    return out;
}

Node decode_node(const QNode& q) {
    Node n{};
    n.valid = q.valid;
    for (int lane = 0; lane < kWidth; ++lane) {
        const bool valid = (q.valid >> lane) & 1u;
        for (int a = 0; a < 3; ++a) {
            n.box[a][0][lane] = valid ? decode_plane(q.origin[a], q.exponent[a], q.q[a][0][lane]) : INFINITY;
            n.box[a][1][lane] = valid ? decode_plane(q.origin[a], q.exponent[a], q.q[a][1][lane]) : -INFINITY;
        }
        n.child[lane] = valid ? q.child[lane] & kMaxIndex : 0;
        n.leaf_size[lane] = uint8_t(valid ? q.child[lane] >> kQIndexBits : 0);
    }
    return n;
}

void decode_nodes(std::span<const QNode> q, AlignedVector<Node, 64>& out) {
    out.resize(q.size());
    for (size_t k = 0; k < q.size(); ++k) out[k] = decode_node(q[k]);
    // Children come after their parents: one backward pass sees every child grown first.
    for (size_t k = q.size(); k-- > 0;) {
        Node& n = out[k];
        for (int lane = 0; lane < kWidth; ++lane) {
            if (!((n.valid >> lane) & 1u) || n.leaf_size[lane] != 0) continue;
            const Node& c = out[n.child[lane]];
            for (int cl = 0; cl < kWidth; ++cl) {
                if (!((c.valid >> cl) & 1u)) continue;
                for (int a = 0; a < 3; ++a) {
                    n.box[a][0][lane] = std::fmin(n.box[a][0][lane], c.box[a][0][cl]);
                    n.box[a][1][lane] = std::fmax(n.box[a][1][lane], c.box[a][1][cl]);
                }
            }
        }
    }
}

void set_plane_bounds(TraceContext& ctx, const QNode* nodes, size_t count) {
    float lo[3] = {INFINITY, INFINITY, INFINITY};
    float hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t k = 0; k < count; ++k) {
        const Node n = decode_node(nodes[k]);
        TraceContext one;
        set_plane_bounds(one, &n, 1);
        for (int a = 0; a < 3; ++a) {
            lo[a] = one.plane_lo[a] < lo[a] ? one.plane_lo[a] : lo[a];
            hi[a] = one.plane_hi[a] > hi[a] ? one.plane_hi[a] : hi[a];
        }
    }
    for (int a = 0; a < 3; ++a) ctx.plane_lo[a] = lo[a], ctx.plane_hi[a] = hi[a];
}

}  // namespace thicket::bvh8
