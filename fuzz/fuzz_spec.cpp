// Spec strings: parsed, and when they parse, built over a small scene and traced (every option
// value the parser lets through must give a working structure).
#include "fuzz_common.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > 256) return 0;  // specs are short; longer inputs only slow the search down
    static const thicket::Scene scene = thicket::load_scene("cornell");
    thicket::AccelSpec spec;
    try {
        spec = thicket::parse_accel_spec(thicket::fuzz::as_text(data, size));
    } catch (const thicket::Error&) {
        return 0;
    }
    try {
        const auto accel = thicket::build_accel(spec, scene);
        const thicket::Ray ray{{0.2f, 1.0f, 3.0f}, 0.0f, {0.0f, -0.1f, -1.0f}, thicket::kInfinity};
        accel->intersect(ray);
        accel->occluded(ray);
        accel->stats();
    } catch (const thicket::Error&) {
    }
    return 0;
}
