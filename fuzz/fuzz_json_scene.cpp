// JSON scenes of meshes and shapes: loading checks every field; then a few rays through brute
// force run each shape kernel with the fuzzed parameters, which must stay within their
// documented work bounds (libFuzzer's -timeout catches one that does not).
#include <cstdlib>
#include <string>

#include "fuzz_common.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

namespace {

/// True if the text asks for a subdivision level above 5 ("level" followed by a number). Levels
/// 6..8 are in the documented range and legitimately take seconds (level 8 of the cube is
/// 786,432 triangles and their BVH: over 10 s under ASan), which libFuzzer's timeout would report;
/// the unit tests cover them. A key spelled with escapes slips through: then only a timeout.
bool asks_for_a_deep_subdivision(const std::string& text) {
    for (size_t at = text.find("\"level\""); at != std::string::npos; at = text.find("\"level\"", at + 1)) {
        size_t i = at + 7;
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\n' || text[i] == '\r' || text[i] == ':'))
            ++i;
        const char* begin = text.c_str() + i;
        char* end = nullptr;
        const double level = std::strtod(begin, &end);
        if (end != begin && !(level <= 5.0)) return true;
    }
    return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(thicket::fuzz::as_text(data, size));
    if (asks_for_a_deep_subdivision(text)) return 0;
    const std::string path = thicket::fuzz::scratch_file("in.json", text);
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
