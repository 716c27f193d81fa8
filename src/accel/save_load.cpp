// The saved-structure container: a fixed header (magic, format version, byte-order mark,
// scene fingerprint and size, spec), then the structure's own payload with its checksum.
// Everything is checked before the payload is handed to the structure's loader.
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/core/hash.h"

namespace thicket {

namespace {

constexpr char kMagic[8] = {'T', 'H', 'I', 'C', 'K', 'E', 'T', '\0'};
constexpr uint32_t kFormatVersion = 1;
constexpr uint32_t kByteOrderMark = 0x01020304u;
constexpr uint32_t kMaxSpecLength = 4096;

template <class T>
void put(std::ostream& out, const T& v) {
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
T get(std::istream& in, const std::string& path, const char* what) {
    T v{};
    if (!in.read(reinterpret_cast<char*>(&v), sizeof(T)))
        throw Error(path + ": truncated file (ends inside the header's " + what + ")");
    return v;
}

}  // namespace

void save_accel(const Accel& accel, const Scene& scene, const std::string& path) {
    std::ostringstream payload_stream;
    accel.save(payload_stream);
    const std::string payload = payload_stream.str();

    // Write beside the target and rename, so a failed save never leaves a half file behind.
    const std::string tmp = path + ".tmp-thicket";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw FileError(path + ": cannot open for writing");
        out.write(kMagic, sizeof kMagic);
        put(out, kFormatVersion);
        put(out, kByteOrderMark);
        put(out, scene.fingerprint());
        put(out, uint64_t(scene.primitive_count()));
        const std::string& spec = accel.spec();
        put(out, uint32_t(spec.size()));
        out.write(spec.data(), std::streamsize(spec.size()));
        put(out, uint64_t(payload.size()));
        put(out, fnv1a(payload.data(), payload.size()));
        out.write(payload.data(), std::streamsize(payload.size()));
        if (!out.flush()) {
            out.close();
            std::filesystem::remove(tmp);
            throw Error(path + ": write failed (disk full?)");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp);
        throw Error(path + ": cannot create file: " + ec.message());
    }
}

std::unique_ptr<Accel> load_accel(const std::string& path, const Scene& scene) {
    const auto start = std::chrono::steady_clock::now();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path + ": cannot open saved structure (no such file or not readable)");
    char magic[8] = {};
    if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0)
        throw Error(path + ": not a thicket structure file (bad magic; write one with `thicket build`)");
    const auto version = get<uint32_t>(in, path, "version");
    if (version != kFormatVersion)
        throw Error(path + ": written in structure-file format version " + std::to_string(version) +
                    ", this build reads version " + std::to_string(kFormatVersion) + "; rebuild it with `thicket build`");
    if (get<uint32_t>(in, path, "byte-order mark") != kByteOrderMark)
        throw Error(path + ": written on a machine of the other byte order");
    const auto fingerprint = get<uint64_t>(in, path, "scene fingerprint");
    const auto prims = get<uint64_t>(in, path, "primitive count");
    if (fingerprint != scene.fingerprint() || prims != scene.primitive_count())
        throw Error(path + ": built for another scene (" + std::to_string(prims) + " primitives) than '" +
                    scene.name + "' (" + std::to_string(scene.primitive_count()) +
                    " primitives, different geometry); rebuild it for this scene");
    const auto spec_len = get<uint32_t>(in, path, "spec length");
    if (spec_len > kMaxSpecLength) throw Error(path + ": corrupt header (spec length " + std::to_string(spec_len) + ")");
    std::string spec_text(spec_len, '\0');
    if (!in.read(spec_text.data(), spec_len)) throw Error(path + ": truncated file (ends inside the spec)");
    const auto payload_len = get<uint64_t>(in, path, "payload length");
    const auto checksum = get<uint64_t>(in, path, "checksum");

    const auto here = in.tellg();
    in.seekg(0, std::ios::end);
    const auto end = in.tellg();
    if (end < here || uint64_t(end - here) != payload_len)
        throw Error(path + ": truncated or padded file (payload is " + std::to_string(uint64_t(end - here)) +
                    " bytes, header says " + std::to_string(payload_len) + ")");
    in.seekg(here);
    std::string payload(payload_len, '\0');
    if (!in.read(payload.data(), std::streamsize(payload_len))) throw Error(path + ": read error in payload");
    if (fnv1a(payload.data(), payload.size()) != checksum)
        throw Error(path + ": corrupt file (checksum mismatch)");

    AccelSpec spec;
    try {
        spec = parse_accel_spec(spec_text);
    } catch (const Error& e) {
        throw Error(path + ": saved spec is not understood by this build: " + e.what());
    }
    const AccelInfo* info = find_accel(spec.name);
    if (!info->load) throw Error(path + ": structure '" + spec.name + "' cannot be loaded from a file");
    std::istringstream payload_in(payload);
    std::unique_ptr<Accel> accel;
    try {
        accel = info->load(payload_in, scene, spec);
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    accel->set_origin(spec.str(), ms);
    return accel;
}

}  // namespace thicket
