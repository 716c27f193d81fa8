// PLY meshes, and PLY files read as subdivision cages (the polygon-size path of the same parser).
#include "fuzz_common.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = thicket::fuzz::scratch_file("in.ply", thicket::fuzz::as_text(data, size));
    try {
        thicket::load_ply(path);
    } catch (const thicket::Error&) {
    }
    try {
        thicket::load_control_mesh(path);
    } catch (const thicket::Error&) {
    }
    return 0;
}
