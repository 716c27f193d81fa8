// The numbers and lists the command line takes: one input line per parser (camera, image size,
// ray-set size, growth sizes, view, ray-set list).
#include <vector>

#include "fuzz_common.h"
#include "thicket/bench/compare.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/core/error.h"
#include "thicket/render/camera.h"
#include "thicket/render/views.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string_view text = thicket::fuzz::as_text(data, size);
    std::vector<std::string_view> lines;
    while (lines.size() < 6) {
        const size_t nl = text.find('\n');
        lines.push_back(text.substr(0, nl));
        if (nl == std::string_view::npos) break;
        text.remove_prefix(nl + 1);
    }
    lines.resize(6);
    auto guard = [](auto&& f) {
        try {
            f();
        } catch (const thicket::Error&) {
        }
    };
    guard([&] { thicket::parse_camera(lines[0]); });
    guard([&] {
        int w = 0, h = 0;
        thicket::parse_image_size(lines[1], w, h);
    });
    guard([&] {
        thicket::RaySetOptions o;
        thicket::parse_ray_set_size(lines[2], o);
    });
    guard([&] { thicket::parse_size_list(lines[3]); });
    guard([&] { thicket::parse_view(lines[4]); });
    guard([&] { thicket::parse_ray_set_list(lines[5]); });
    return 0;
}
