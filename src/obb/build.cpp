// OBB tree construction: the BVH's topology renumbered root first, and one oriented box per
// node fitted to the points of the primitives below it (principal axes from the points'
// covariance, by Jacobi rotations; the world axes where they enclose the points in less area).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "thicket/core/error.h"
#include "thicket/core/ray.h"
#include "thicket/obb/build.h"
#include "thicket/util/parallel.h"

namespace thicket {

namespace {

/// Eigenvectors of the symmetric 3x3 matrix `a` (overwritten) as the columns of `v`, by cyclic
/// Jacobi rotations; converges in a handful of sweeps for 3x3.
void jacobi_eigenvectors(double a[3][3], double v[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[i][j] = i == j ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * diag || off == 0.0) return;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {  // a = J^T a J, J the rotation in the (p, q) plane
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
}

/// A node's primitives, as the range prim_indices[first .. first+count) of the BVH.
struct Range {
    uint32_t first = 0, count = 0;
};

/// The points of the primitives in `r`, visited in order (Indexed: BvhData or ObbData, whose
/// prim_indices the ranges index).
template <class Indexed, class F>
void for_points(const Indexed& bvh, const ObbPoints& pts, Range r, F&& f) {
    for (uint32_t i = r.first; i < r.first + r.count; ++i) {
        const uint32_t p = bvh.prim_indices[i];
        for (uint32_t k = pts.offsets[p]; k < pts.offsets[p + 1]; ++k) f(pts.points[k]);
    }
}

/// The box with the given orthonormal axes around the points of `r`, grown by `margin`.
template <class Indexed>
ObbNode fit_box(const Indexed& bvh, const ObbPoints& pts, Range r, const Vec3 axis[3], Vec3 origin, float margin) {
    ObbNode node;
    for (int k = 0; k < 3; ++k) node.axis[k] = axis[k];
    Vec3 lo(kInfinity), hi(-kInfinity);
    for_points(bvh, pts, r, [&](Vec3 p) {
        const Vec3 v = p - origin;
        const Vec3 q(dot(axis[0], v), dot(axis[1], v), dot(axis[2], v));
        lo = min(lo, q);
        hi = max(hi, q);
    });
    const Vec3 mid = (lo + hi) * 0.5f;
    node.center = origin + axis[0] * mid.x + axis[1] * mid.y + axis[2] * mid.z;
    // The half extents measured around the stored centre, with the very arithmetic the
    // traversal applies to the ray's origin, then grown: relative for the rounding of the
    // products, absolute for points far from the centre.
    Vec3 half(0.0f);
    for_points(bvh, pts, r, [&](Vec3 p) {
        const Vec3 v = p - node.center;
        half = max(half, abs(Vec3(dot(axis[0], v), dot(axis[1], v), dot(axis[2], v))));
    });
    node.half = half * (1.0f + 1e-5f) + Vec3(margin);
    return node;
}

/// The oriented box of the points of `r`: principal axes, unless the world axes (or the
/// principal axes fail: flat or repeated points) give a box of less area.
template <class Indexed>
ObbNode fit_node(const Indexed& bvh, const ObbPoints& pts, Range r, ObbFit fit, float margin) {
    const Vec3 world[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double mean[3] = {0, 0, 0};
    size_t n = 0;
    for_points(bvh, pts, r, [&](Vec3 p) {
        for (int k = 0; k < 3; ++k) mean[k] += p[k];
        ++n;
    });
    for (double& m : mean) m /= double(std::max<size_t>(n, 1));
    const Vec3 origin{float(mean[0]), float(mean[1]), float(mean[2])};
    const ObbNode aligned = fit_box(bvh, pts, r, world, origin, margin);
    if (fit == ObbFit::Axes) return aligned;
    double cov[3][3] = {};
    for_points(bvh, pts, r, [&](Vec3 p) {
        const double d[3] = {p.x - mean[0], p.y - mean[1], p.z - mean[2]};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) cov[i][j] += d[i] * d[j];
    });
    double v[3][3];
    jacobi_eigenvectors(cov, v);
    Vec3 axis[3];
    axis[0] = Vec3(float(v[0][0]), float(v[1][0]), float(v[2][0]));
    axis[1] = Vec3(float(v[0][1]), float(v[1][1]), float(v[2][1]));
    const float l0 = length(axis[0]);
    if (!(l0 > 0.5f) || !std::isfinite(l0)) return aligned;
    axis[0] = axis[0] / l0;
    axis[1] = axis[1] - axis[0] * dot(axis[0], axis[1]);
    const float l1 = length(axis[1]);
    if (!(l1 > 0.5f) || !std::isfinite(l1)) return aligned;
    axis[1] = axis[1] / l1;
    axis[2] = cross(axis[0], axis[1]);
    const ObbNode oriented = fit_box(bvh, pts, r, axis, origin, margin);
    return obb_area(oriented) < obb_area(aligned) ? oriented : aligned;
}

/// Each node's primitive range: a subtree's primitives are contiguous in prim_indices, and
/// children follow their parents, so a backward sweep has both children's before the parent's.
std::vector<Range> subtree_ranges(const ObbData& obb) {
    std::vector<Range> ranges(obb.nodes.size());
    for (size_t n = obb.nodes.size(); n-- > 0;) {
        const ObbNode& o = obb.nodes[n];
        if (o.is_leaf()) {
            ranges[n] = {o.leftFirst, o.count};
        } else {
            const Range a = ranges[o.leftFirst], b = ranges[o.leftFirst + 1];
            ranges[n] = {std::min(a.first, b.first), a.count + b.count};
        }
    }
    return ranges;
}

/// The mean of the points of `r`: the origin fit_box measures from.
template <class Indexed>
Vec3 mean_point(const Indexed& tree, const ObbPoints& pts, Range r) {
    double mean[3] = {0, 0, 0};
    size_t n = 0;
    for_points(tree, pts, r, [&](Vec3 p) {
        for (int k = 0; k < 3; ++k) mean[k] += p[k];
        ++n;
    });
    for (double& m : mean) m /= double(std::max<size_t>(n, 1));
    return {float(mean[0]), float(mean[1]), float(mean[2])};
}

}  // namespace

void refit_obb(ObbData& obb, const ObbPoints& points, float scale, unsigned threads) {
    if (obb.nodes.empty()) return;
    if (points.offsets.size() != obb.prim_indices.size() + 1)
        throw Error("OBB refit: " + std::to_string(points.offsets.size()) + " point offsets for " +
                    std::to_string(obb.prim_indices.size()) + " primitives");
    const std::vector<Range> ranges = subtree_ranges(obb);
    const float margin = 4e-6f * scale;
    // Every node is fitted to its own points, as the build does, so no box depends on another
    // and the nodes go in parallel; the axes stay, only the centre and extents follow the points.
    parallel_for(obb.nodes.size(), 64, threads, [&](size_t begin, size_t end) {
        for (size_t n = begin; n < end; ++n) {
            ObbNode& o = obb.nodes[n];
            const ObbNode fitted = fit_box(obb, points, ranges[n], o.axis, mean_point(obb, points, ranges[n]), margin);
            o.center = fitted.center;
            o.half = fitted.half;
        }
    });
}

float obb_area(const ObbNode& node) {
    const Vec3 e = node.half * 2.0f;
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

ObbData build_obb(const BvhData& bvh, const ObbPoints& points, ObbFit fit, float scale, unsigned threads) {
    ObbData obb;
    obb.prim_indices = bvh.prim_indices;
    if (bvh.nodes_used == 0) return obb;
    if (points.offsets.size() != bvh.prim_indices.size() + 1)
        throw Error("OBB build: " + std::to_string(points.offsets.size()) + " point offsets for " +
                    std::to_string(bvh.prim_indices.size()) + " primitives");
    // Renumber root first with children in adjacent pairs, and find each node's primitive
    // range (a subtree's primitives are contiguous in the BVH's index array).
    std::vector<uint32_t> source{0};  // BVH node of each OBB node
    for (size_t n = 0; n < source.size(); ++n) {
        const BvhNode& b = bvh.nodes[source[n]];
        if (!b.is_leaf()) {
            source.push_back(b.leftFirst);
            source.push_back(b.leftFirst + 1);
        }
    }
    obb.nodes.resize(source.size());
    std::vector<Range> ranges;
    uint32_t next_child = 1;
    for (size_t n = 0; n < source.size(); ++n) {
        const BvhNode& b = bvh.nodes[source[n]];
        if (b.is_leaf()) {
            obb.nodes[n].leftFirst = b.leftFirst;
            obb.nodes[n].count = b.count;
        } else {
            obb.nodes[n].leftFirst = next_child;
            next_child += 2;
        }
    }
    ranges = subtree_ranges(obb);
    const float margin = 4e-6f * scale;
    parallel_for(obb.nodes.size(), 64, threads, [&](size_t begin, size_t end) {
        for (size_t n = begin; n < end; ++n) {
            const ObbNode fitted = fit_node(bvh, points, ranges[n], fit, margin);
            ObbNode& o = obb.nodes[n];
            for (int k = 0; k < 3; ++k) o.axis[k] = fitted.axis[k];
            o.center = fitted.center;
            o.half = fitted.half;
        }
    });
    return obb;
}

}  // namespace thicket
