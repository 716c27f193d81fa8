// PLY reader: ASCII and both binary byte orders, any element/property layout. The whole file is
// read into memory first; every count is checked against the bytes that remain before anything
// is allocated, so a corrupt header cannot trigger a huge allocation or a read past the end.
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/core/huge_pages.h"
#include "thicket/util/input_file.h"
#include "thicket/scene/loaders.h"

namespace thicket {
namespace {

static_assert(sizeof(Vec3) == 12, "the binary fast path copies packed float triples into Vec3");

enum class Scalar : uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };
enum class Format : uint8_t { ascii, binary_le, binary_be };

size_t scalar_size(Scalar t) {
    switch (t) {
        case Scalar::i8:
        case Scalar::u8: return 1;
        case Scalar::i16:
        case Scalar::u16: return 2;
        case Scalar::i32:
        case Scalar::u32:
        case Scalar::f32: return 4;
        case Scalar::f64: return 8;
    }
    return 0;
}

bool is_integer(Scalar t) { return t != Scalar::f32 && t != Scalar::f64; }

bool parse_scalar(std::string_view s, Scalar& out) {
    struct Name {
        const char* name;
        Scalar type;
    };
    static constexpr Name names[] = {
        {"char", Scalar::i8},   {"int8", Scalar::i8},     {"uchar", Scalar::u8},   {"uint8", Scalar::u8},
        {"short", Scalar::i16}, {"int16", Scalar::i16},   {"ushort", Scalar::u16}, {"uint16", Scalar::u16},
        {"int", Scalar::i32},   {"int32", Scalar::i32},   {"uint", Scalar::u32},   {"uint32", Scalar::u32},
        {"float", Scalar::f32}, {"float32", Scalar::f32}, {"double", Scalar::f64}, {"float64", Scalar::f64},
    };
    for (const Name& n : names) {
        if (s == n.name) {
            out = n.type;
            return true;
        }
    }
    return false;
}

struct Property {
    std::string name;
    Scalar type = Scalar::f32;  ///< the item type, for lists
    bool is_list = false;
    Scalar count_type = Scalar::u8;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
    size_t line = 0;  ///< header line that declared it, for messages
};

/// File contents, without the zero-fill a std::vector would spend on 16 MB first.
struct FileBytes {
    std::unique_ptr<unsigned char[]> bytes;
    size_t size = 0;
    const unsigned char* data() const { return bytes.get(); }
};

/// Reads a whole file; throws Error naming the path when it cannot.
FileBytes read_whole_file(const std::string& path) {
    // A device or FIFO is refused (/dev/zero never ends); the size must fit in memory.
    const uint64_t expected = check_regular_input(path, "PLY file");
    check_memory(expected, path + ": reading this " + std::to_string(expected) + "-byte file");
    std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) throw FileError(path + ": cannot open: " + std::strerror(errno));
    size_t capacity = size_t(expected) + 1;
    FileBytes out{std::unique_ptr<unsigned char[]>(new unsigned char[capacity]), 0};
    advise_huge_pages(out.bytes.get(), capacity);
    // Read until EOF rather than trusting the size, so a file that changes under us stays safe.
    for (;;) {
        out.size += std::fread(out.bytes.get() + out.size, 1, capacity - out.size, f.get());
        if (out.size < capacity) break;
        std::unique_ptr<unsigned char[]> bigger(new unsigned char[capacity * 2]);
        std::memcpy(bigger.get(), out.bytes.get(), out.size);
        out.bytes = std::move(bigger);
        capacity *= 2;
    }
    if (std::ferror(f.get())) throw Error(path + ": read error");
    return out;
}

template <class U>
U byteswap_uint(U v) {
    if constexpr (sizeof(U) == 2)
        return __builtin_bswap16(v);
    else if constexpr (sizeof(U) == 4)
        return __builtin_bswap32(v);
    else
        return __builtin_bswap64(v);
}

/// Loads one binary scalar as a double (exact for every PLY type); the caller checked the bounds.
template <class T>
double load_as(const unsigned char* p, bool swap) {
    if constexpr (sizeof(T) == 1) {
        T v;
        std::memcpy(&v, p, 1);
        return double(v);
    } else {
        using U = std::conditional_t<sizeof(T) == 2, uint16_t,
                                     std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>;
        U u;
        std::memcpy(&u, p, sizeof(U));
        if (swap) u = byteswap_uint(u);
        return double(std::bit_cast<T>(u));
    }
}

double load_binary(const unsigned char* p, Scalar t, bool swap) {
    switch (t) {
        case Scalar::i8: return load_as<int8_t>(p, swap);
        case Scalar::u8: return load_as<uint8_t>(p, swap);
        case Scalar::i16: return load_as<int16_t>(p, swap);
        case Scalar::u16: return load_as<uint16_t>(p, swap);
        case Scalar::i32: return load_as<int32_t>(p, swap);
        case Scalar::u32: return load_as<uint32_t>(p, swap);
        case Scalar::f32: return load_as<float>(p, swap);
        case Scalar::f64: return load_as<double>(p, swap);
    }
    return 0.0;
}

/// Binary body cursor. Every read is bounds-checked; a failed read returns false.
class BinarySource {
public:
    BinarySource(const unsigned char* begin, const unsigned char* end, bool swap)
        : p_(begin), end_(end), swap_(swap) {}

    size_t remaining() const { return size_t(end_ - p_); }
    const unsigned char* cursor() const { return p_; }
    void advance(size_t n) { p_ += n; }
    bool swapped() const { return swap_; }

    bool read(Scalar t, double& out) {
        const size_t n = scalar_size(t);
        if (remaining() < n) return false;
        out = load_binary(p_, t, swap_);
        p_ += n;
        return true;
    }
    bool skip(Scalar t, uint64_t count) {
        const size_t n = scalar_size(t);
        if (count > remaining() / n) return false;
        p_ += count * n;
        return true;
    }
    bool can_hold(Scalar t, uint64_t count) const { return count <= remaining() / scalar_size(t); }
    std::string problem() const { return "unexpected end of file"; }

private:
    const unsigned char* p_;
    const unsigned char* end_;
    bool swap_;
};

/// ASCII body cursor: whitespace-separated tokens, with the line number kept for messages.
class AsciiSource {
public:
    AsciiSource(const char* begin, const char* end, size_t line) : p_(begin), end_(end), line_(line) {}

    bool read(Scalar t, double& out) {
        const std::string_view tok = next();
        if (tok.empty()) return false;
        const char* first = tok.data() + (tok[0] == '+' ? 1 : 0);
        const char* last = tok.data() + tok.size();
        if (is_integer(t)) {
            long long v = 0;
            auto r = std::from_chars(first, last, v);
            if (r.ec != std::errc() || r.ptr != last) return bad(tok);
            out = double(v);
        } else {
            double v = 0;
            auto r = std::from_chars(first, last, v);
            if (r.ec != std::errc() || r.ptr != last) return bad(tok);
            out = v;
        }
        return true;
    }
    bool skip(Scalar t, uint64_t count) {
        double ignored;
        for (uint64_t i = 0; i < count; ++i)
            if (!read(t, ignored)) return false;
        return true;
    }
    /// Text has no fixed width: a list is bounded by the tokens actually read.
    bool can_hold(Scalar, uint64_t) const { return true; }
    std::string problem() const {
        if (!bad_token_.empty()) return "line " + std::to_string(line_) + ": bad number '" + bad_token_ + "'";
        return "line " + std::to_string(line_) + ": unexpected end of file";
    }
    size_t remaining() const { return size_t(end_ - p_); }
    /// The line of the first non-blank text left, or 0 when only whitespace remains.
    size_t leftover_line() { return next().empty() ? 0 : line_; }

private:
    std::string_view next() {
        while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) {
            if (*p_ == '\n') ++line_;
            ++p_;
        }
        const char* start = p_;
        while (p_ < end_ && *p_ != ' ' && *p_ != '\t' && *p_ != '\r' && *p_ != '\n') ++p_;
        return {start, size_t(p_ - start)};
    }
    bool bad(std::string_view tok) {
        bad_token_ = std::string(tok.substr(0, 32));
        return false;
    }

    const char* p_;
    const char* end_;
    size_t line_;
    std::string bad_token_;
};

class PlyParser {
public:
    PlyParser(const std::string& path, FileBytes data) : path_(path), data_(std::move(data)) {}
    /// Also records every face's vertex count (its fan has count - 2 triangles) into `sizes`.
    void record_polygon_sizes(std::vector<uint32_t>& sizes) { polygon_sizes_ = &sizes; }

    TriangleMesh parse() {
        parse_header();
        locate_elements();
        if (format_ == Format::ascii) {
            const char* base = reinterpret_cast<const char*>(data_.data());
            AsciiSource src(base + body_, base + data_.size, header_lines_ + 1);
            for (const Element& e : elements_) parse_element(src, e);
            // Like the .npy and saved-structure readers: data the header does not account for
            // means the header (or the file) is not what it claims.
            if (const size_t line = src.leftover_line())
                fail("line " + std::to_string(line) + ": data after the last element the header declares");
        } else {
            const bool swap = (format_ == Format::binary_le) != (std::endian::native == std::endian::little);
            BinarySource src(data_.data() + body_, data_.data() + data_.size, swap);
            for (const Element& e : elements_) parse_element(src, e);
            if (src.remaining() != 0)
                fail(std::to_string(src.remaining()) + " bytes after the last element the header declares");
        }
        return std::move(mesh_);
    }

private:
    [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }
    [[noreturn]] void fail_line(size_t line, const std::string& what) const {
        fail("header line " + std::to_string(line) + ": " + what);
    }

    void parse_header() {
        const std::string_view text(reinterpret_cast<const char*>(data_.data()), data_.size);
        size_t pos = 0, line = 0;
        bool have_format = false, ended = false;
        if (text.substr(0, 4) != "ply\n" && text.substr(0, 5) != "ply\r\n")
            fail("not a PLY file (the first line is not 'ply')");
        while (pos < text.size() && !ended) {
            size_t nl = text.find('\n', pos);
            std::string_view row = text.substr(pos, nl == std::string_view::npos ? nl : nl - pos);
            pos = nl == std::string_view::npos ? text.size() : nl + 1;
            ++line;
            if (!row.empty() && row.back() == '\r') row.remove_suffix(1);
            const std::vector<std::string_view> tok = split(row);
            if (line == 1) continue;  // "ply", checked above
            if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
            if (tok[0] == "format") {
                if (have_format) fail_line(line, "second format line");
                if (tok.size() != 3)
                    fail_line(line, "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
                if (tok[1] == "ascii")
                    format_ = Format::ascii;
                else if (tok[1] == "binary_little_endian")
                    format_ = Format::binary_le;
                else if (tok[1] == "binary_big_endian")
                    format_ = Format::binary_be;
                else
                    fail_line(line, "unknown format '" + std::string(tok[1]) + "'");
                if (tok[2] != "1.0" && tok[2] != "1")
                    fail_line(line, "unsupported PLY version '" + std::string(tok[2]) + "'");
                have_format = true;
            } else if (tok[0] == "element") {
                if (tok.size() != 3) fail_line(line, "expected 'element <name> <count>'");
                Element e;
                e.name = std::string(tok[1]);
                e.line = line;
                auto r = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
                if (r.ec != std::errc() || r.ptr != tok[2].data() + tok[2].size())
                    fail_line(line, "bad element count '" + std::string(tok[2]) + "'");
                for (const Element& other : elements_)
                    if (other.name == e.name) fail_line(line, "element '" + e.name + "' declared twice");
                elements_.push_back(std::move(e));
            } else if (tok[0] == "property") {
                if (elements_.empty()) fail_line(line, "property before any element");
                elements_.back().props.push_back(parse_property(tok, line));
            } else if (tok[0] == "end_header") {
                ended = true;
            } else {
                fail_line(line,
                          "unexpected header line '" + printable(row.substr(0, 40)) + "' (no end_header?)");
            }
        }
        if (!ended) fail_line(line, "the file ends before end_header");
        if (!have_format) fail_line(line, "no format line before end_header");
        body_ = pos;
        header_lines_ = line;
    }

    Property parse_property(const std::vector<std::string_view>& tok, size_t line) const {
        Property p;
        if (tok.size() >= 2 && tok[1] == "list") {
            if (tok.size() != 5) fail_line(line, "expected 'property list <count type> <item type> <name>'");
            if (!parse_scalar(tok[2], p.count_type))
                fail_line(line, "unknown property type '" + std::string(tok[2]) + "'");
            if (!is_integer(p.count_type)) fail_line(line, "list count type must be an integer type");
            if (!parse_scalar(tok[3], p.type))
                fail_line(line, "unknown property type '" + std::string(tok[3]) + "'");
            p.is_list = true;
            p.name = std::string(tok[4]);
        } else {
            if (tok.size() != 3) fail_line(line, "expected 'property <type> <name>'");
            if (!parse_scalar(tok[1], p.type))
                fail_line(line, "unknown property type '" + std::string(tok[1]) + "'");
            p.name = std::string(tok[2]);
        }
        return p;
    }

    /// Header text for messages; binary bytes would garble a terminal.
    static std::string printable(std::string_view s) {
        std::string out(s);
        for (char& c : out)
            if (c < 0x20 || c > 0x7e) c = '?';
        return out;
    }

    static std::vector<std::string_view> split(std::string_view s) {
        std::vector<std::string_view> out;
        size_t i = 0;
        while (i < s.size()) {
            while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
            size_t j = i;
            while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
            if (j > i) out.push_back(s.substr(i, j - i));
            i = j;
        }
        return out;
    }

    /// Finds the vertex and face elements and the properties the mesh needs from them.
    void locate_elements() {
        for (size_t i = 0; i < elements_.size(); ++i) {
            if (elements_[i].name == "vertex") vertex_elem_ = i;
            if (elements_[i].name == "face") face_elem_ = i;
        }
        if (vertex_elem_ == npos) fail("no 'element vertex' in the header");
        if (face_elem_ == npos) fail("no 'element face' in the header");
        const Element& v = elements_[vertex_elem_];
        const char* axes[3] = {"x", "y", "z"};
        for (int a = 0; a < 3; ++a) {
            for (size_t i = 0; i < v.props.size(); ++i)
                if (v.props[i].name == axes[a]) xyz_[a] = i;
            if (xyz_[a] == npos || v.props[xyz_[a]].is_list)
                fail_line(v.line, std::string("element 'vertex' has no scalar property '") + axes[a] + "'");
        }
        // Any coordinate stored as double: the mesh keeps them all in double (positions_double)
        // beside the float positions, for `precision=double` structures.
        for (int a = 0; a < 3; ++a) keep_double_ = keep_double_ || v.props[xyz_[a]].type == Scalar::f64;
        if (v.count > std::numeric_limits<uint32_t>::max())
            fail_line(v.line,
                      "too many vertices (" + std::to_string(v.count) + "); at most 2^32-1 are supported");
        const Element& f = elements_[face_elem_];
        for (size_t i = 0; i < f.props.size(); ++i)
            if (f.props[i].name == "vertex_indices" || f.props[i].name == "vertex_index") index_prop_ = i;
        if (index_prop_ == npos || !f.props[index_prop_].is_list)
            fail_line(f.line, "element 'face' has no list property 'vertex_indices' or 'vertex_index'");
    }

    std::string row_context(const Element& e, uint64_t row) const {
        return "element '" + e.name + "' row " + std::to_string(row) + " of " + std::to_string(e.count);
    }

    /// Rejects a count that cannot fit in what is left of the file, before anything is reserved.
    void check_count(const BinarySource& src, const Element& e) const {
        size_t min_row = 0;
        for (const Property& p : e.props) min_row += scalar_size(p.is_list ? p.count_type : p.type);
        if (min_row != 0 && e.count > src.remaining() / min_row)
            fail("element '" + e.name + "' declares " + std::to_string(e.count) + " rows of at least " +
                 std::to_string(min_row) + " bytes, but only " + std::to_string(src.remaining()) +
                 " bytes remain (truncated or corrupt file)");
    }

    /// Capacity to reserve for an element: bounded by what the remaining bytes can hold, so a
    /// bogus count only costs what the file could really contain.
    template <class Source>
    static size_t plausible_rows(const Source& src, const Element& e) {
        const size_t per_row = std::max<size_t>(1, e.props.size()) * 2;  // ASCII: a digit and a separator
        return size_t(std::min<uint64_t>(e.count, src.remaining() / per_row + 1));
    }

    void parse_element(BinarySource& src, const Element& e) {
        if (e.props.empty()) return;  // rows without properties occupy no bytes
        check_count(src, e);
        if (!src.swapped() && &e == &elements_[vertex_elem_] && try_fast_vertices(src, e)) return;
        if (!src.swapped() && &e == &elements_[face_elem_] && try_fast_faces(src, e)) return;
        parse_generic(src, e);
    }

    void parse_element(AsciiSource& src, const Element& e) {
        if (e.props.empty()) return;
        parse_generic(src, e);
    }

    /// The common layout `float x, y, z` only: one memcpy.
    bool try_fast_vertices(BinarySource& src, const Element& e) {
        if (e.props.size() != 3) return false;
        for (int a = 0; a < 3; ++a)
            if (xyz_[a] != size_t(a) || e.props[a].type != Scalar::f32) return false;
        reserve_huge(mesh_.positions, size_t(e.count));
        mesh_.positions.resize(size_t(e.count));
        if (e.count == 0) return true;  // data() may be null, which memcpy must not see
        std::memcpy(mesh_.positions.data(), src.cursor(), size_t(e.count) * 12);
        src.advance(size_t(e.count) * 12);
        return true;
    }

    /// The common layout `list uchar int|uint vertex_indices` only. Indices are written straight
    /// into the output; triangles (nearly every row in practice) take a branch of their own.
    bool try_fast_faces(BinarySource& src, const Element& e) {
        if (e.props.size() != 1) return false;
        const Property& p = e.props[0];
        if (p.count_type != Scalar::u8 || (p.type != Scalar::i32 && p.type != Scalar::u32)) return false;
        const uint32_t vcount = uint32_t(elements_[vertex_elem_].count);
        std::vector<uint32_t>& out = mesh_.indices;
        size_t w = out.size();
        // A valid row takes at least 13 bytes, so this never exceeds what the file can hold.
        reserve_huge(out, w + 3 * size_t(std::min<uint64_t>(e.count, src.remaining() / 13)));
        out.resize(w + 3 * size_t(std::min<uint64_t>(e.count, src.remaining() / 13)));
        uint32_t poly[255];
        for (uint64_t row = 0; row < e.count; ++row) {
            if (src.remaining() < 1) fail(row_context(e, row) + ": unexpected end of file");
            const unsigned n = *src.cursor();
            if (src.remaining() < 1 + 4 * size_t(n)) fail(row_context(e, row) + ": unexpected end of file");
            if (n < 3) fail_polygon_size(row, n);
            if (polygon_sizes_) polygon_sizes_->push_back(n);
            if (n == 3)
                std::memcpy(poly, src.cursor() + 1, 12);  // fixed size: no memcpy dispatch
            else
                std::memcpy(poly, src.cursor() + 1, 4 * size_t(n));
            src.advance(1 + 4 * size_t(n));
            // A negative int32 becomes a huge uint32 here, so one compare covers both ends.
            for (unsigned k = 0; k < n; ++k)
                if (poly[k] >= vcount)
                    fail_index(row, p.type == Scalar::i32 ? double(int32_t(poly[k])) : double(poly[k]));
            if (w + 3 * (n - 2) > out.size()) out.resize(std::max(2 * out.size(), w + 3 * (n - 2)));
            uint32_t* dst = out.data() + w;
            for (unsigned k = 2; k < n; ++k, dst += 3) {
                dst[0] = poly[0];
                dst[1] = poly[k - 1];
                dst[2] = poly[k];
            }
            w += 3 * (n - 2);
        }
        out.resize(w);
        return true;
    }

    [[noreturn]] void fail_polygon_size(uint64_t face, uint64_t n) const {
        fail("face " + std::to_string(face) + " has " + std::to_string(n) +
             " vertex indices; at least 3 are needed");
    }
    [[noreturn]] void fail_index(uint64_t face, double index) const {
        const bool integral = std::fabs(index) < 9e18 && index == std::trunc(index);
        const std::string shown = integral ? std::to_string(int64_t(index)) : std::to_string(index);
        fail("face " + std::to_string(face) + ": vertex index " + shown + " is out of range (" +
             std::to_string(elements_[vertex_elem_].count) + " vertices)");
    }

    template <class Source>
    void parse_generic(Source& src, const Element& e) {
        const bool is_vertex = &e == &elements_[vertex_elem_];
        const bool is_face = &e == &elements_[face_elem_];
        const double vcount = double(elements_[vertex_elem_].count);
        if (is_vertex) mesh_.positions.reserve(plausible_rows(src, e));
        if (is_vertex && keep_double_) mesh_.positions_double.reserve(plausible_rows(src, e));
        if (is_face) mesh_.indices.reserve(plausible_rows(src, e) * 3);
        std::vector<uint32_t> poly;
        for (uint64_t row = 0; row < e.count; ++row) {
            Vec3 v;
            Vec3d vd;
            for (size_t pi = 0; pi < e.props.size(); ++pi) {
                const Property& p = e.props[pi];
                double value = 0;
                if (!p.is_list) {
                    if (!src.read(p.type, value))
                        fail(row_context(e, row) + ", property '" + p.name + "': " + src.problem());
                    if (is_vertex) {
                        for (int a = 0; a < 3; ++a)
                            if (xyz_[a] == pi) {
                                v[a] = float(value);
                                vd[a] = value;
                            }
                    }
                    continue;
                }
                double count = 0;
                if (!src.read(p.count_type, count))
                    fail(row_context(e, row) + ", list '" + p.name + "' count: " + src.problem());
                if (count < 0)
                    fail(row_context(e, row) + ", list '" + p.name + "': negative count " +
                         std::to_string(int64_t(count)));
                const uint64_t n = uint64_t(count);
                if (!(is_face && pi == index_prop_)) {
                    if (!src.skip(p.type, n))
                        fail(row_context(e, row) + ", list '" + p.name + "': " + src.problem());
                    continue;
                }
                if (n < 3) fail_polygon_size(row, n);
                if (polygon_sizes_) polygon_sizes_->push_back(uint32_t(n));
                if (!src.can_hold(p.type, n))
                    fail(row_context(e, row) + ", list '" + p.name + "' of " + std::to_string(n) +
                         " items: " + src.problem());
                poly.clear();
                for (uint64_t k = 0; k < n; ++k) {
                    if (!src.read(p.type, value))
                        fail(row_context(e, row) + ", list '" + p.name + "': " + src.problem());
                    if (!(value >= 0 && value < vcount) || value != std::trunc(value)) fail_index(row, value);
                    poly.push_back(uint32_t(value));
                }
                for (size_t k = 2; k < poly.size(); ++k) {
                    mesh_.indices.push_back(poly[0]);
                    mesh_.indices.push_back(poly[k - 1]);
                    mesh_.indices.push_back(poly[k]);
                }
            }
            if (is_vertex) {
                mesh_.positions.push_back(v);
                if (keep_double_) mesh_.positions_double.push_back(vd);
            }
        }
    }

    static constexpr size_t npos = size_t(-1);

    std::string path_;
    FileBytes data_;
    Format format_ = Format::ascii;
    std::vector<Element> elements_;
    size_t body_ = 0;
    size_t header_lines_ = 0;
    size_t vertex_elem_ = npos, face_elem_ = npos, index_prop_ = npos;
    size_t xyz_[3] = {npos, npos, npos};
    bool keep_double_ = false;
    TriangleMesh mesh_;
    std::vector<uint32_t>* polygon_sizes_ = nullptr;
};

}  // namespace

/// Reads a PLY mesh (ASCII or binary); polygons are fan-triangulated in file order. Throws
/// thicket::Error("<path>: ...") for unreadable, malformed, truncated or unsupported files.
TriangleMesh load_ply(const std::string& path) {
    PlyParser parser(path, read_whole_file(path));
    return parser.parse();
}

TriangleMesh load_ply(const std::string& path, std::vector<uint32_t>& polygon_sizes) {
    PlyParser parser(path, read_whole_file(path));
    polygon_sizes.clear();
    parser.record_polygon_sizes(polygon_sizes);
    return parser.parse();
}

}  // namespace thicket
