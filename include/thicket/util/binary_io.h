#pragma once
/// Raw binary I/O of plain data for the structures' saved payloads (the header with checksum and
/// scene fingerprint is save_accel's): values and arrays as they are in memory, and the one
/// checked reader every saved-file loader reads its arrays through. Its refusals name the payload
/// and the field ("BIH payload truncated in nodes"); load_accel puts the file's name in front.
#include <cstddef>
#include <cstdint>
#include <istream>
#include <limits>
#include <ostream>
#include <string>
#include <type_traits>

#include "thicket/core/error.h"

namespace thicket {

/// Writes the bytes of one plain value.
template <class T>
void write_value(std::ostream& out, const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

/// Writes `count` plain values from `data`.
template <class T>
void write_array(std::ostream& out, const T* data, size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(count * sizeof(T)));
}

/// Writes v's length as a Count, then its elements as they are in memory: what
/// PayloadReader::counted_array() reads.
template <class Count, class V>
void write_counted_array(std::ostream& out, const V& v) {
    write_value(out, Count(v.size()));
    write_array(out, v.data(), v.size());
}

/// Reads the values of one payload, from the stream's position to its end. A count is checked
/// against its bound and against the bytes left before anything is allocated for it, so a
/// corrupt count is refused without allocating more than the payload's own size.
class PayloadReader {
public:
    /// No bound but the bytes left (`most` of array()).
    static constexpr uint64_t kAnyCount = std::numeric_limits<uint64_t>::max();

    PayloadReader(std::istream& in, const char* payload) : in_(in), payload_(payload) {
        const auto here = in.tellg();
        if (here < 0) return;  // a stream that cannot tell: the bounds alone guard allocation
        in.seekg(0, std::ios::end);
        const auto end = in.tellg();
        in.seekg(here);
        left_ = end < here ? 0 : uint64_t(end - here);
    }

    template <class T>
    void value(T& v, const char* what) {
        array(&v, 1, what);
    }
    /// Reads `count` values into memory the caller has sized.
    template <class T>
    void array(T* data, size_t count, const char* what) {
        static_assert(std::is_trivially_copyable_v<T>);
        if (!in_.read(reinterpret_cast<char*>(data), std::streamsize(count * sizeof(T))))
            throw Error(std::string(payload_) + " payload truncated in " + what);
        if (left_ != kAnyCount) left_ -= count * sizeof(T);
    }

    /// Reads `count` elements into `v` (a vector of plain values), refusing a count above `most`
    /// ("<payload> payload claims N <what>, at most M for this scene") or one the bytes left cannot
    /// hold ("<payload> payload truncated in <what>: ...") before resizing `v`.
    template <class V>
    void array(V& v, uint64_t count, uint64_t most, const char* what) {
        using T = typename V::value_type;
        if (count > most)
            throw Error(std::string(payload_) + " payload claims " + std::to_string(count) + " " + what + ", at most " +
                        std::to_string(most) + " for this scene");
        if (count > left_ / sizeof(T))
            throw Error(std::string(payload_) + " payload truncated in " + what + ": " + std::to_string(count) +
                        " entries of " + std::to_string(sizeof(T)) + " bytes, " + std::to_string(left_) +
                        " bytes left");
        v.resize(size_t(count));
        array(v.data(), v.size(), what);
    }

    /// Reads what write_counted_array<Count>() wrote: the count, then array() with it.
    template <class Count, class V>
    void counted_array(V& v, uint64_t most, const char* what) {
        Count count{};
        value(count, what);
        array(v, uint64_t(count), most, what);
    }

    /// Refuses a payload with bytes after the last field.
    void end() {
        if (in_.peek() != std::char_traits<char>::eof())
            throw Error(std::string(payload_) + " payload has trailing bytes");
    }

private:
    std::istream& in_;
    const char* payload_;
    uint64_t left_ = kAnyCount;  ///< bytes not yet read; kAnyCount when the stream cannot tell
};

}  // namespace thicket
