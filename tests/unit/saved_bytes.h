#pragma once
// Editing saved structure files the way a careless tool or a fuzzer would: the bytes changed,
// then the checksum recomputed so that the change reaches the structure's validator; and the
// determinism tests' scribbled build. Shared by the saved_*_test.cpp and build_determinism_test.cpp files.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket::testing {

/// Where the spec, the checksum and the payload lie in saved_accel_bytes()'s layout.
struct SavedLayout {
    size_t spec_at, spec_len, checksum_at, payload_at;
};
inline SavedLayout layout_of(const std::string& bytes) {
    const size_t spec_len_at = 8 + 4 + 4 + 8 + 8;  // magic, version, byte order, fingerprint, size
    uint32_t spec_len = 0;
    std::memcpy(&spec_len, bytes.data() + spec_len_at, 4);
    const size_t spec_at = spec_len_at + 4;
    return {spec_at, spec_len, spec_at + spec_len + 8, spec_at + spec_len + 16};
}

/// The bytes with the checksum recomputed over their (changed) spec and payload.
inline std::string reseal(std::string bytes) {
    const SavedLayout l = layout_of(bytes);
    const uint64_t sum = saved_accel_checksum(std::string_view(bytes).substr(l.spec_at, l.spec_len),
                                              std::string_view(bytes).substr(l.payload_at));
    std::memcpy(bytes.data() + l.checksum_at, &sum, 8);
    return bytes;
}

/// The saved bytes with another payload (its length and the checksum rewritten to match).
inline std::string with_payload(const std::string& bytes, const std::string& payload) {
    const SavedLayout l = layout_of(bytes);
    std::string out = bytes.substr(0, l.payload_at) + payload;
    const uint64_t length = payload.size();
    std::memcpy(out.data() + l.checksum_at - 8, &length, 8);
    return reseal(out);
}

/// The message load_accel_bytes() refuses `bytes` with, or "" when it loads.
inline std::string error_of(const std::string& bytes, const Scene& scene) {
    try {
        load_accel_bytes(bytes, scene, "saved.bin");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// Fills the stack below the caller with `value`, so that whatever a later call leaves
/// uninitialised there reads differently from one build to the next.
[[gnu::noinline]] inline void scribble_stack(unsigned char value) {
    volatile unsigned char buffer[1 << 16];
    for (size_t i = 0; i < sizeof buffer; ++i) buffer[i] = value;
}

/// The saved bytes of `spec` built over `scene` on `threads` threads, the stack scribbled with
/// `value` first (the determinism tests' build).
inline std::string saved_after_scribble(const std::string& spec, const Scene& scene, unsigned threads,
                                        unsigned char value) {
    scribble_stack(value);
    return saved_accel_bytes(*build_accel(spec, scene, threads), scene);
}

}  // namespace thicket::testing
