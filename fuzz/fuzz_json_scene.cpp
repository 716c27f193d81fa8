// JSON scenes of meshes and shapes: loading checks every field; then a few rays through brute
// force run each shape kernel with the fuzzed parameters, which must stay within their
// documented work bounds (libFuzzer's -timeout catches one that does not).
#include "fuzz_common.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = thicket::fuzz::scratch_file("in.json", thicket::fuzz::as_text(data, size));
    thicket::Scene scene;
    try {
        scene = thicket::load_json_scene(path);
    } catch (const thicket::Error&) {
        return 0;
    }
    if (scene.primitive_count() > 64) return 0;  // the kernels, not brute force over many shapes
    try {
        const auto accel = thicket::build_accel("brute", scene);
        const thicket::Aabb b = scene.bounds();
        const thicket::Vec3 c = b.empty() ? thicket::Vec3{} : b.center();
        const thicket::Ray rays[] = {{c + thicket::Vec3{0, 0, 10}, 0.0f, {0, 0, -1}, thicket::kInfinity},
                                     {c + thicket::Vec3{3, 2, 10}, 0.0f, {-0.3f, -0.2f, -1}, thicket::kInfinity}};
        for (const thicket::Ray& r : rays) {
            accel->intersect(r);
            accel->occluded(r);
        }
    } catch (const thicket::Error&) {
    }
    return 0;
}
