#pragma once
// Fragments of triangles for the autopartition builder: convex polygons, each a piece of one
// original triangle. A fragment that was never cut refers to its triangle's float vertices; a
// cut one keeps its vertices in double, so that pieces of pieces stay on their triangle.
#include <cmath>
#include <span>
#include <vector>

#include "fragments.h"
#include "thicket/core/aabb.h"

namespace thicket::bsp_build {

class PolygonFragments {
public:
    static constexpr bool kPolygons = true;

    struct Frag {
        uint32_t prim;
        uint32_t first;  ///< first vertex in Set::verts (pieces only)
        uint32_t count;  ///< vertices of a piece; 0: the whole original triangle
    };
    struct Set {
        std::vector<Frag> frags;
        std::vector<P3> verts;
        size_t size() const { return frags.size(); }
    };

    /// `tolerance`: a vertex within this distance of a plane counts as lying in it.
    PolygonFragments(std::span<const std::array<Vec3, 3>> triangles, double tolerance)
        : tris_(triangles), tolerance_(tolerance) {}

    /// Every triangle, whole.
    Set initial() const {
        Set s;
        s.frags.resize(tris_.size());
        for (uint32_t i = 0; i < tris_.size(); ++i) s.frags[i] = {i, 0, 0};
        return s;
    }

    uint32_t prim(const Set& s, size_t i) const { return s.frags[i].prim; }

    /// Calls f(P3) for each vertex of fragment i, in order around the polygon.
    template <class F>
    void for_vertices(const Set& s, size_t i, F&& f) const {
        const Frag& fr = s.frags[i];
        if (fr.count == 0) {
            for (const Vec3& v : tris_[fr.prim]) f(to_p3(v));
        } else {
            for (uint32_t k = fr.first; k < fr.first + fr.count; ++k) f(s.verts[k]);
        }
    }

    /// The points whose distances to a plane decide fragment i's placement: its vertices.
    void gather(const Set& s, size_t i, std::vector<P3>& out) const {
        for_vertices(s, i, [&](const P3& p) { out.push_back(p); });
    }
    double tolerance() const { return tolerance_; }

    /// Fragment i's box, rounded outwards to float.
    Aabb bounds(const Set& s, size_t i) const {
        poly_.clear();
        gather(s, i, poly_);
        return points_box(poly_.data(), poly_.size());
    }

    /// The supporting plane of fragment i's triangle (none for a degenerate triangle). The offset
    /// is taken at the centroid, so the float plane passes as close to all three vertices as it can.
    template <class Out>
    void candidates(const Set& s, size_t i, const Aabb&, Out& out) const {
        const auto& t = tris_[s.frags[i].prim];
        const P3 a = to_p3(t[0]), b = to_p3(t[1]), c = to_p3(t[2]);
        const P3 n = normal(a, b, c);
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const P3 e1 = sub(b, a), e2 = sub(c, a);
        // The same rule as Triangles::degenerate: edges parallel to within 1e-6 have no plane.
        if (!(len > 1e-6 * std::sqrt(dot(e1, e1)) * std::sqrt(dot(e2, e2)))) return;
        BspPlane p;
        p.normal = Vec3(float(n[0] / len), float(n[1] / len), float(n[2] / len));
        p.offset = float((double(p.normal.x) * (a[0] + b[0] + c[0]) + double(p.normal.y) * (a[1] + b[1] + c[1]) +
                          double(p.normal.z) * (a[2] + b[2] + c[2])) /
                         3.0);
        out.push_back(p);
    }

    /// Second-choice planes, for nodes where no supporting plane separates anything (typically
    /// coplanar triangles, such as a tessellated floor): the planes through each edge of fragment
    /// i's triangle, perpendicular to the triangle; they partition its plane as the 2D
    /// autopartition would.
    template <class Out>
    void edge_candidates(const Set& s, size_t i, const Aabb&, Out& out) const {
        const auto& t = tris_[s.frags[i].prim];
        const P3 v[3] = {to_p3(t[0]), to_p3(t[1]), to_p3(t[2])};
        const P3 n = normal(v[0], v[1], v[2]);
        if (!(dot(n, n) > 0.0)) return;
        for (int k = 0; k < 3; ++k) {
            const P3& a = v[k];
            const P3& b = v[(k + 1) % 3];
            const P3 e = sub(b, a);
            const P3 m = {e[1] * n[2] - e[2] * n[1], e[2] * n[0] - e[0] * n[2], e[0] * n[1] - e[1] * n[0]};
            const double len = std::sqrt(dot(m, m));
            if (!(len > 0.0)) continue;
            BspPlane p;
            p.normal = Vec3(float(m[0] / len), float(m[1] / len), float(m[2] / len));
            p.offset = float(0.5 * (double(p.normal.x) * (a[0] + b[0]) + double(p.normal.y) * (a[1] + b[1]) +
                                    double(p.normal.z) * (a[2] + b[2])));
            out.push_back(p);
        }
    }

    /// Straddles when vertices lie beyond the tolerance on both sides. A fragment lying in the
    /// plane goes to the side its triangle's front face looks into (the normal's side when the
    /// winding agrees with the plane's normal), where the rays that meet its front face come from.
    Placement place(const Set& s, size_t i, const BspPlane& plane) const {
        bool front = false, back = false;
        for_vertices(s, i, [&](const P3& p) {
            const double d = plane_distance(plane, p);
            front |= d > tolerance_;
            back |= d < -tolerance_;
        });
        if (front && back) return {Side::Straddle, false};
        if (front) return {Side::Front, false};
        if (back) return {Side::Back, false};
        const auto& t = tris_[s.frags[i].prim];
        const P3 n = normal(to_p3(t[0]), to_p3(t[1]), to_p3(t[2]));
        const double facing = n[0] * plane.normal.x + n[1] * plane.normal.y + n[2] * plane.normal.z;
        return {facing < 0.0 ? Side::Front : Side::Back, true};
    }

    /// Appends fragment i to `back` or `front` as placed, or cuts it into one piece for each
    /// (Sutherland-Hodgman against the plane: vertices within the tolerance go to both pieces,
    /// crossing edges are cut exactly where the plane meets them).
    void send(const Set& from, size_t i, const BspPlane& plane, Placement where, Set& back, Set& front) const {
        const Frag& fr = from.frags[i];
        if (where.side != Side::Straddle) {
            Set& to = where.side == Side::Back ? back : front;
            if (fr.count == 0) {
                to.frags.push_back(fr);
            } else {
                to.frags.push_back({fr.prim, uint32_t(to.verts.size()), fr.count});
                to.verts.insert(to.verts.end(), from.verts.begin() + fr.first, from.verts.begin() + fr.first + fr.count);
            }
            return;
        }
        poly_.clear();
        for_vertices(from, i, [&](const P3& p) { poly_.push_back(p); });
        const uint32_t bfirst = uint32_t(back.verts.size()), ffirst = uint32_t(front.verts.size());
        const size_t n = poly_.size();
        dist_.resize(n);
        for (size_t k = 0; k < n; ++k) dist_[k] = plane_distance(plane, poly_[k]);
        auto side = [&](size_t k) { return dist_[k] > tolerance_ ? 1 : (dist_[k] < -tolerance_ ? -1 : 0); };
        for (size_t k = 0; k < n; ++k) {
            const size_t next = (k + 1) % n;
            const int sk = side(k), sn = side(next);
            if (sk >= 0) front.verts.push_back(poly_[k]);
            if (sk <= 0) back.verts.push_back(poly_[k]);
            if (sk * sn < 0) {
                const double s = dist_[k] / (dist_[k] - dist_[next]);
                P3 q;
                for (int a = 0; a < 3; ++a) q[a] = poly_[k][a] + s * (poly_[next][a] - poly_[k][a]);
                front.verts.push_back(q);
                back.verts.push_back(q);
            }
        }
        back.frags.push_back({fr.prim, bfirst, uint32_t(back.verts.size() - bfirst)});
        front.frags.push_back({fr.prim, ffirst, uint32_t(front.verts.size() - ffirst)});
    }

    /// Whether fragment i is a piece of a cut triangle (not the whole triangle).
    bool is_piece(const Set& s, size_t i) const { return s.frags[i].count != 0; }

    /// Area of fragment i (in double, fanned from its first vertex).
    double area(const Set& s, size_t i) const {
        poly_.clear();
        for_vertices(s, i, [&](const P3& p) { poly_.push_back(p); });
        P3 sum{0, 0, 0};
        for (size_t k = 1; k + 1 < poly_.size(); ++k) {
            const P3 c = normal(poly_[0], poly_[k], poly_[k + 1]);
            for (int a = 0; a < 3; ++a) sum[a] += c[a];
        }
        return 0.5 * std::sqrt(dot(sum, sum));
    }

    double prim_area(uint32_t prim) const {
        const auto& t = tris_[prim];
        const P3 n = normal(to_p3(t[0]), to_p3(t[1]), to_p3(t[2]));
        return 0.5 * std::sqrt(dot(n, n));
    }

    void polygon(const Set& s, size_t i, std::vector<P3>& out) const {
        out.clear();
        gather(s, i, out);
    }

private:
    static P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
    static double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
    /// (b - a) x (c - a)
    static P3 normal(const P3& a, const P3& b, const P3& c) {
        const P3 e1 = sub(b, a), e2 = sub(c, a);
        return {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    }

    std::span<const std::array<Vec3, 3>> tris_;
    double tolerance_;
    mutable std::vector<P3> poly_;     // scratch: one fragment's vertices
    mutable std::vector<double> dist_; // scratch: their distances to the plane
};

}  // namespace thicket::bsp_build
