// OBJ meshes with their MTL materials, and OBJ files read as subdivision cages. The input is the
// OBJ text, optionally followed by a line "#MTL" and the text of m.mtl (which the OBJ may name
// with "mtllib m.mtl"), so that one input mutates both files.
#include "fuzz_common.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text = thicket::fuzz::as_text(data, size);
    const size_t split = text.find("\n#MTL\n");
    const std::string_view obj = text.substr(0, split);
    const std::string_view mtl = split == std::string_view::npos ? std::string_view() : text.substr(split + 6);
    thicket::fuzz::scratch_file("m.mtl", mtl);
    const std::string path = thicket::fuzz::scratch_file("in.obj", obj);
    try {
        thicket::load_obj(path);
    } catch (const thicket::Error&) {
    }
    try {
        thicket::load_control_mesh(path);
    } catch (const thicket::Error&) {
    }
    return 0;
}
