#pragma once
/// Raw binary I/O of plain data for the structures' saved payloads (the header with checksum and
/// scene fingerprint is save_accel's): values and arrays as they are in memory, reads that name
/// what was truncated.
#include <cstddef>
#include <istream>
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

/// Reads values of one payload; a short read throws Error "<payload> payload truncated in <what>".
class PayloadReader {
public:
    PayloadReader(std::istream& in, const char* payload) : in_(in), payload_(payload) {}

    template <class T>
    void value(T& v, const char* what) {
        array(&v, 1, what);
    }
    template <class T>
    void array(T* data, size_t count, const char* what) {
        static_assert(std::is_trivially_copyable_v<T>);
        if (!in_.read(reinterpret_cast<char*>(data), std::streamsize(count * sizeof(T))))
            throw Error(std::string(payload_) + " payload truncated in " + what);
    }

private:
    std::istream& in_;
    const char* payload_;
};

}  // namespace thicket
