// .npy files through every reader `thicket trace` and the tests use.
#include "fuzz_common.h"
#include "thicket/core/error.h"
#include "thicket/util/npy.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = thicket::fuzz::scratch_file("in.npy", thicket::fuzz::as_text(data, size));
    try {
        thicket::read_npy_float(path);
    } catch (const thicket::Error&) {
    }
    try {
        thicket::read_npy_matrix(path, 8);
    } catch (const thicket::Error&) {
    }
    try {
        thicket::read_npy_u8(path);
    } catch (const thicket::Error&) {
    }
    try {
        thicket::read_npy_hits(path);
    } catch (const thicket::Error&) {
    }
    return 0;
}
