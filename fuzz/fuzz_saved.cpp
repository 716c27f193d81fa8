// Saved structures (`thicket build` files) of every loadable structure, over the built-in Cornell
// box, or over a unit cube of 12 triangles (the scene of fuzz/corpus/saved/cube.obj, for the
// structures whose Cornell files are over -max_len: the tetrahedral mesh). The harness recomputes the checksum over the (mutated) spec and payload before loading,
// so the mutations reach the structures' validators instead of stopping at the checksum. A file
// that loads must answer like brute force: a validator that lets a wrong tree through is a
// finding even when nothing crashes.
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "fuzz_common.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/scene.h"

namespace {

const size_t kSpecLengthAt = 8 + 4 + 4 + 8 + 8;  // magic, version, byte order, fingerprint, size

/// The unit cube of cube.obj: 8 corners, 12 triangles (a closed mesh TetGen meshes whole in a
/// few dozen tetrahedra, so its saved tetra file fits -max_len=4096).
thicket::Scene unit_cube() {
    thicket::Scene s;
    s.name = "cube.obj";
    for (int c = 0; c < 8; ++c) {
        // cube.obj's vertex order: the bottom square counter-clockwise, then the top one.
        const float x = (c % 4 == 1 || c % 4 == 2) ? 1.0f : 0.0f, y = (c % 4 >= 2) ? 1.0f : 0.0f;
        s.mesh.positions.push_back({x, y, c >= 4 ? 1.0f : 0.0f});
    }
    s.mesh.indices = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                      1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
    return s;
}

/// Brute force's answers with one triangle test (the loaded structure's isect= option: the two
/// tests legitimately differ on edges).
struct Reference {
    thicket::Scene scene;
    std::vector<thicket::Ray> rays;
    std::vector<thicket::Hit> hits;
    Reference(thicket::Scene s, const std::string& isect) : scene(std::move(s)) {
        const auto brute = thicket::build_accel("brute:isect=" + isect, scene);
        const thicket::Aabb b = scene.bounds();
        // A fan of rays from in front of the box and from inside it, through the whole scene.
        for (int i = 0; i < 64; ++i) {
            const float u = float(i % 8) / 7.0f, v = float(i / 8) / 7.0f;
            const thicket::Vec3 target = b.min + (b.max - b.min) * thicket::Vec3{u, v, 0.5f};
            const thicket::Vec3 from = i % 2 ? b.center() : b.center() + thicket::Vec3{0, 0, 3 * (b.max.z - b.min.z)};
            rays.push_back({from, 0.0f, target - from, thicket::kInfinity});
            hits.push_back(brute->intersect(rays.back()));
        }
    }
};

/// The references of one scene, one per triangle test.
struct References {
    Reference moller, watertight;
    explicit References(const thicket::Scene& s) : moller(s, "moller"), watertight(s, "watertight") {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const References cornell(thicket::load_scene("cornell")), cube(unit_cube());
    // The scene the file says it was built for (its primitive count; a mismatch is refused).
    uint64_t prims = 0;
    if (size >= 32) std::memcpy(&prims, data + 24, 8);
    const References& refs = prims == cube.moller.scene.primitive_count() ? cube : cornell;
    const Reference& ref = refs.moller;
    std::string bytes(reinterpret_cast<const char*>(data), size);
    if (bytes.size() >= kSpecLengthAt + 4) {
        uint32_t spec_len = 0;
        std::memcpy(&spec_len, bytes.data() + kSpecLengthAt, 4);
        const size_t spec_at = kSpecLengthAt + 4, sum_at = spec_at + size_t(spec_len) + 8;
        if (spec_len <= 4096 && sum_at + 8 <= bytes.size()) {
            const uint64_t sum = thicket::saved_accel_checksum(std::string_view(bytes).substr(spec_at, spec_len),
                                                               std::string_view(bytes).substr(sum_at + 8));
            std::memcpy(bytes.data() + sum_at, &sum, 8);
        }
    }
    std::unique_ptr<thicket::Accel> accel;
    try {
        accel = thicket::load_accel_bytes(bytes, ref.scene, "fuzzed");
    } catch (const thicket::Error&) {
        return 0;
    }
    const Reference& truth = thicket::parse_accel_spec(accel->spec()).get("isect") == "watertight" ? refs.watertight : refs.moller;
    // Every saved format is proved on load (docs/fuzzing.md): whatever loads answers like brute force.
    for (size_t i = 0; i < truth.rays.size(); ++i) {
        const thicket::Hit h = accel->intersect(truth.rays[i]);
        const thicket::Hit& want = truth.hits[i];
        const bool same = h.found() == want.found() && (!h.found() || std::fabs(h.t - want.t) <= 1e-5f * want.t);
        if (!same || accel->occluded(truth.rays[i]) != want.found()) {
            std::fprintf(stderr, "loaded %s answers ray %zu unlike brute force\n", accel->spec().c_str(), i);
            std::abort();
        }
    }
    return 0;
}
