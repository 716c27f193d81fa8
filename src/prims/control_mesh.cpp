// Control meshes: validation (OpenSubdiv tolerates non-manifold input by tagging it; we refuse
// it, so that the limit surface is the one the user expects) and the cube. Reading cages from
// files is scene loading (src/scene/cage_loader.cpp): primitives do not call loaders.
#include "thicket/prims/control_mesh.h"

#include <cmath>
#include <numeric>
#include <unordered_map>

#include "thicket/core/error.h"

namespace thicket {
namespace {

std::string vec_str(Vec3 v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

uint64_t edge_key(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

/// Union-find over the faces around one vertex.
uint32_t find(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

void validate_control_mesh(const ControlMesh& cage) {
    const size_t nv = cage.positions.size();
    if (cage.face_sizes.empty()) throw Error("control mesh: no faces");
    for (size_t i = 0; i < nv; ++i) {
        const Vec3 p = cage.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error("control mesh: vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
    const uint64_t total = std::accumulate(cage.face_sizes.begin(), cage.face_sizes.end(), uint64_t(0));
    if (total != cage.indices.size())
        throw Error("control mesh: face sizes add up to " + std::to_string(total) + " but there are " +
                    std::to_string(cage.indices.size()) + " indices");

    // Directed edges: each (a, b) at most once (else two faces agree on a direction: the
    // orientation is inconsistent, or the edge has more than two faces).
    std::unordered_map<uint64_t, uint32_t> directed;  // (from, to) -> face
    std::unordered_map<uint64_t, int> undirected;
    std::vector<uint32_t> used(nv, 0);
    size_t offset = 0;
    for (size_t f = 0; f < cage.face_sizes.size(); ++f) {
        const uint32_t n = cage.face_sizes[f];
        if (n < 3) throw Error("control mesh: face " + std::to_string(f) + " has " + std::to_string(n) + " vertices (at least 3 needed)");
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t a = cage.indices[offset + k];
            if (a >= nv)
                throw Error("control mesh: face " + std::to_string(f) + " uses vertex " + std::to_string(a) +
                            ", out of range (" + std::to_string(nv) + " vertices)");
            for (uint32_t m = 0; m < k; ++m)
                if (cage.indices[offset + m] == a)
                    throw Error("control mesh: face " + std::to_string(f) + " uses vertex " + std::to_string(a) + " twice");
            ++used[a];
        }
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t a = cage.indices[offset + k], b = cage.indices[offset + (k + 1) % n];
            const uint64_t key = (uint64_t(a) << 32) | b;
            if (!directed.emplace(key, uint32_t(f)).second)
                throw Error("control mesh: edge " + std::to_string(a) + "-" + std::to_string(b) + " is traversed the same way by faces " +
                            std::to_string(directed[key]) + " and " + std::to_string(f) +
                            " (inconsistent orientation or more than two faces on the edge)");
            if (++undirected[edge_key(a, b)] > 2)
                throw Error("control mesh: edge " + std::to_string(a) + "-" + std::to_string(b) + " has more than two faces (non-manifold)");
        }
        offset += n;
    }
    for (size_t i = 0; i < nv; ++i)
        if (!used[i]) throw Error("control mesh: vertex " + std::to_string(i) + " " + vec_str(cage.positions[i]) + " is used by no face");

    // Each vertex's faces must form one fan: faces around v are joined when they share an edge
    // at v (both directions of the edge present). Two fans meeting only at v is a "bowtie".
    std::vector<std::vector<uint32_t>> faces_at(nv);
    std::vector<uint32_t> face_start(cage.face_sizes.size());
    offset = 0;
    for (size_t f = 0; f < cage.face_sizes.size(); ++f) {
        face_start[f] = uint32_t(offset);
        for (uint32_t k = 0; k < cage.face_sizes[f]; ++k) faces_at[cage.indices[offset + k]].push_back(uint32_t(f));
        offset += cage.face_sizes[f];
    }
    for (uint32_t v = 0; v < nv; ++v) {
        const auto& around = faces_at[v];
        std::vector<uint32_t> parent(around.size());
        std::iota(parent.begin(), parent.end(), 0u);
        std::unordered_map<uint32_t, uint32_t> slot;  // face -> position in `around`
        for (uint32_t s = 0; s < around.size(); ++s) slot[around[s]] = s;
        size_t groups = around.size();
        for (uint32_t s = 0; s < around.size(); ++s) {
            const uint32_t f = around[s], n = cage.face_sizes[f], o = face_start[f];
            for (uint32_t k = 0; k < n; ++k) {
                if (cage.indices[o + k] != v) continue;
                const uint32_t next = cage.indices[o + (k + 1) % n];
                // The face on the other side of edge v->next traverses next->v.
                const auto it = directed.find((uint64_t(next) << 32) | v);
                if (it == directed.end()) continue;
                const uint32_t a = find(parent, s), b = find(parent, slot.at(it->second));
                if (a != b) parent[a] = b, --groups;
            }
        }
        if (groups > 1)
            throw Error("control mesh: vertex " + std::to_string(v) + " " + vec_str(cage.positions[v]) + " joins " +
                        std::to_string(groups) + " separate fans of faces (non-manifold vertex)");
    }
}

ControlMesh cube_control_mesh() {
    ControlMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f});
    // Counter-clockwise seen from outside (vertex bit 0 = x, 1 = y, 2 = z).
    const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : faces) {
        m.face_sizes.push_back(4);
        m.indices.insert(m.indices.end(), f, f + 4);
    }
    return m;
}

}  // namespace thicket
