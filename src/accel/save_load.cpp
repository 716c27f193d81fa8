// The saved-structure container: a fixed header (magic, format version, byte-order mark,
// scene fingerprint and size, spec), then the structure's own payload. The checksum covers the
// spec text and the payload (format 2: in format 1 it covered the payload only, so an edited
// "max-leaf=8" loaded as another structure). Everything is checked before the payload is handed
// to the structure's loader, whose validator then proves what its traversal relies on.
#include <chrono>
#include <cstring>
#include <sstream>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/core/hash.h"
#include "thicket/util/atomic_file.h"
#include "thicket/util/input_file.h"

namespace thicket {

namespace {

constexpr char kMagic[8] = {'T', 'H', 'I', 'C', 'K', 'E', 'T', '\0'};
constexpr uint32_t kFormatVersion = 2;
constexpr uint32_t kByteOrderMark = 0x01020304u;
constexpr uint32_t kMaxSpecLength = 4096;

template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

/// Reads the header field by field, naming the field a short file ends in.
class HeaderReader {
public:
    HeaderReader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}
    template <class T>
    T get(const char* what) {
        T v{};
        std::memcpy(&v, take(sizeof(T), what).data(), sizeof(T));
        return v;
    }
    std::string_view take(size_t n, const char* what) {
        if (bytes_.size() - pos_ < n) throw Error(name_ + ": truncated file (ends inside the header's " + what + ")");
        const std::string_view s = bytes_.substr(pos_, n);
        pos_ += n;
        return s;
    }
    std::string_view rest() const { return bytes_.substr(pos_); }

private:
    std::string_view bytes_;
    const std::string& name_;
    size_t pos_ = 0;
};

}  // namespace

uint64_t saved_accel_checksum(std::string_view spec, std::string_view payload) {
    return fnv1a(payload.data(), payload.size(), fnv1a(spec.data(), spec.size()));
}

std::string saved_accel_bytes(const Accel& accel, const Scene& scene) {
    std::ostringstream payload_stream;
    accel.save(payload_stream);
    const std::string payload = payload_stream.str();
    const std::string& spec = accel.spec();
    std::string out(kMagic, sizeof kMagic);
    put(out, kFormatVersion);
    put(out, kByteOrderMark);
    put(out, scene.fingerprint());
    put(out, uint64_t(scene.primitive_count()));
    put(out, uint32_t(spec.size()));
    out += spec;
    put(out, uint64_t(payload.size()));
    put(out, saved_accel_checksum(spec, payload));
    out += payload;
    return out;
}

void save_accel(const Accel& accel, const Scene& scene, const std::string& path) {
    write_file_atomically(path, saved_accel_bytes(accel, scene));
}

std::unique_ptr<Accel> load_accel_bytes(std::string_view bytes, const Scene& scene, const std::string& path) {
    HeaderReader in(bytes, path);
    if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
        throw Error(path + ": not a thicket structure file (bad magic; write one with `thicket build`)");
    in.take(sizeof kMagic, "magic");
    const auto version = in.get<uint32_t>("version");
    if (version != kFormatVersion)
        throw Error(path + ": written in structure-file format version " + std::to_string(version) +
                    ", this build reads version " + std::to_string(kFormatVersion) + "; rebuild it with `thicket build`");
    if (in.get<uint32_t>("byte-order mark") != kByteOrderMark)
        throw Error(path + ": written on a machine of the other byte order");
    const auto fingerprint = in.get<uint64_t>("scene fingerprint");
    const auto prims = in.get<uint64_t>("primitive count");
    if (fingerprint != scene.fingerprint() || prims != scene.primitive_count())
        throw Error(path + ": built for another scene (" + std::to_string(prims) + " primitives) than '" +
                    scene.name + "' (" + std::to_string(scene.primitive_count()) +
                    " primitives, different geometry); rebuild it for this scene");
    const auto spec_len = in.get<uint32_t>("spec length");
    if (spec_len > kMaxSpecLength) throw Error(path + ": corrupt header (spec length " + std::to_string(spec_len) + ")");
    const std::string spec_text(in.take(spec_len, "spec"));
    const auto payload_len = in.get<uint64_t>("payload length");
    const auto checksum = in.get<uint64_t>("checksum");
    const std::string_view payload = in.rest();
    if (payload.size() != payload_len)
        throw Error(path + ": truncated or padded file (payload is " + std::to_string(payload.size()) +
                    " bytes, header says " + std::to_string(payload_len) + ")");
    if (saved_accel_checksum(spec_text, payload) != checksum)
        throw Error(path + ": corrupt file (checksum of the spec and payload does not match)");

    AccelSpec spec;
    try {
        spec = parse_accel_spec(spec_text);
    } catch (const Error& e) {
        throw Error(path + ": saved spec is not understood by this build: " + e.what());
    }
    const AccelInfo* info = spec.info;  // set by the parser
    if (!info->load) throw Error(path + ": structure '" + spec.name + "' cannot be loaded from a file");
    std::istringstream payload_in{std::string(payload)};
    std::unique_ptr<Accel> accel;
    try {
        accel = info->load(payload_in, scene, spec);
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
    accel->set_origin(spec.str(), 0.0);
    return accel;
}

std::unique_ptr<Accel> load_accel(const std::string& path, const Scene& scene) {
    const auto start = std::chrono::steady_clock::now();
    const std::string bytes = read_input_file(path, "saved structure");
    std::unique_ptr<Accel> accel = load_accel_bytes(bytes, scene, path);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::string spec = accel->spec();
    accel->set_origin(std::move(spec), ms);
    return accel;
}

}  // namespace thicket
