// glTF: the input is a .glb when it starts with glTF's binary magic, otherwise .gltf text. A
// buffer the file names as "b.bin" exists (16 bytes of zeros and ones) so external buffers are
// exercised too.
#include <cstring>

#include "fuzz_common.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string buffer = thicket::fuzz::scratch_file("b.bin", std::string("\0\0\0\0\0\0\x80?\0\0\x80?\0\0\0\0", 16));
    (void)buffer;
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const std::string path = thicket::fuzz::scratch_file(binary ? "in.glb" : "in.gltf", thicket::fuzz::as_text(data, size));
    try {
        thicket::load_gltf(path);
    } catch (const thicket::Error&) {
    }
    // The scene path too: nodes sharing a mesh become instances, whose transforms are checked there.
    try {
        thicket::load_gltf_scene(path);
    } catch (const thicket::Error&) {
    }
    return 0;
}
