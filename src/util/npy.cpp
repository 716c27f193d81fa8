#include "thicket/util/npy.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>

#include "thicket/core/error.h"
#include "thicket/util/input_file.h"
#include "thicket/util/atomic_file.h"

namespace thicket {

static_assert(std::endian::native == std::endian::little, ".npy I/O assumes a little-endian host");

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr size_t kMagicSize = 6;
constexpr size_t kAlign = 64;
constexpr size_t kGrowthAxisDigits = 21;
constexpr size_t kMaxHeaderLen = 1u << 20;  // sanity bound: real headers are a few hundred bytes

// ---- a parser for the Python literal subset that .npy headers use --------------------------
struct PyValue {
    enum Kind { Str, Int, Bool, None, Tuple, List } kind = None;
    std::string str;
    long long num = 0;
    bool flag = false;
    std::vector<PyValue> items;
};

class HeaderParser {
public:
    HeaderParser(const std::string& path, std::string_view text) : path_(path), s_(text) {}

    std::map<std::string, PyValue> parse_dict() {
        std::map<std::string, PyValue> dict;
        expect('{');
        while (true) {
            skip_space();
            if (peek() == '}') break;
            PyValue key = parse_value();
            if (key.kind != PyValue::Str) fail("dictionary keys must be strings");
            expect(':');
            PyValue value = parse_value();
            if (!dict.emplace(key.str, std::move(value)).second) fail("key '" + key.str + "' appears twice");
            skip_space();
            if (peek() == ',') {
                ++pos_;
                continue;
            }
            if (peek() != '}') fail("expected ',' or '}'");
        }
        ++pos_;
        skip_space();
        if (pos_ != s_.size()) fail("unexpected text after the dictionary");
        return dict;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw Error(path_ + ": malformed .npy header at character " + std::to_string(pos_) + ": " + what);
    }
    char peek() const { return pos_ < s_.size() ? s_[pos_] : '\0'; }
    void skip_space() {
        while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\n' || s_[pos_] == '\t' || s_[pos_] == '\r'))
            ++pos_;
    }
    void expect(char c) {
        skip_space();
        if (peek() != c) fail(std::string("expected '") + c + "'");
        ++pos_;
    }

    PyValue parse_value() {
        skip_space();
        const char c = peek();
        PyValue v;
        if (c == '\'' || c == '"') {
            v.kind = PyValue::Str;
            ++pos_;
            while (pos_ < s_.size() && s_[pos_] != c) {
                if (s_[pos_] == '\\') ++pos_;
                if (pos_ < s_.size()) v.str += s_[pos_++];
            }
            if (pos_ >= s_.size()) fail("unterminated string");
            ++pos_;
        } else if (c == '(' || c == '[') {
            v.kind = c == '(' ? PyValue::Tuple : PyValue::List;
            const char close = c == '(' ? ')' : ']';
            ++pos_;
            while (true) {
                skip_space();
                if (peek() == close) break;
                v.items.push_back(parse_value());
                skip_space();
                if (peek() == ',') {
                    ++pos_;
                    continue;
                }
                if (peek() != close) fail(std::string("expected ',' or '") + close + "'");
            }
            ++pos_;
        } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-') {
            v.kind = PyValue::Int;
            const size_t start = pos_;
            if (c == '-') ++pos_;
            unsigned long long n = 0;
            if (!std::isdigit(static_cast<unsigned char>(peek()))) fail("expected a digit");
            while (std::isdigit(static_cast<unsigned char>(peek()))) {
                const unsigned d = unsigned(peek() - '0');
                if (n > (~0ull - d) / 10) fail("integer too large");
                n = n * 10 + d;
                ++pos_;
            }
            if (peek() == 'L') ++pos_;  // Python 2 long literal, found in old files
            if (n > (1ull << 62)) fail("integer too large: " + std::string(s_.substr(start, pos_ - start)));
            v.num = c == '-' ? -(long long)n : (long long)n;
        } else if (std::isalpha(static_cast<unsigned char>(c))) {
            const size_t start = pos_;
            while (std::isalnum(static_cast<unsigned char>(peek())) || peek() == '_') ++pos_;
            const std::string_view word = s_.substr(start, pos_ - start);
            if (word == "True" || word == "False") {
                v.kind = PyValue::Bool;
                v.flag = word == "True";
            } else if (word == "None") {
                v.kind = PyValue::None;
            } else {
                fail("unexpected name '" + std::string(word) + "'");
            }
        } else {
            fail(c == '\0' ? std::string("unexpected end of header") : std::string("unexpected character '") + c + "'");
        }
        return v;
    }

    const std::string& path_;
    std::string_view s_;
    size_t pos_ = 0;
};

uint64_t read_le(const unsigned char* p, int bytes) {
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

std::string shape_repr(const std::vector<size_t>& shape) {
    std::string s = "(";
    for (size_t i = 0; i < shape.size(); ++i) {
        if (i) s += ", ";
        s += std::to_string(shape[i]);
    }
    if (shape.size() == 1) s += ",";
    return s + ")";
}

std::string descr_repr(const NpyHeader& h) {
    if (h.fields.empty()) return "'" + h.descr + "'";
    std::string s = "[";
    for (size_t i = 0; i < h.fields.size(); ++i)
        s += (i ? ", ('" : "('") + h.fields[i].first + "', '" + h.fields[i].second + "')";
    return s + "]";
}

void write_array(const std::string& path, NpyHeader h, const void* data, size_t bytes) {
    std::string dict = "{'descr': " + descr_repr(h) + ", 'fortran_order': False, 'shape': " + shape_repr(h.shape) + ", }";
    // NumPy leaves room for the first dimension to grow to 21 digits in place; doing the same makes
    // our files byte-identical to numpy.save's.
    if (!h.shape.empty()) {
        const size_t digits = std::to_string(h.shape[0]).size();
        dict.append(kGrowthAxisDigits - std::min(kGrowthAxisDigits, digits), ' ');
    }
    const size_t prefix_v1 = kMagicSize + 2 + 2;
    const bool v2 = dict.size() + 1 + kAlign > 65535;
    const size_t prefix = v2 ? kMagicSize + 2 + 4 : prefix_v1;
    const size_t total = (prefix + dict.size() + 1 + kAlign - 1) / kAlign * kAlign;
    dict.append(total - prefix - dict.size() - 1, ' ');
    dict += '\n';
    std::string head(kMagic, kMagicSize);
    head += char(v2 ? 2 : 1);
    head += char(0);
    const size_t len = dict.size();
    for (int i = 0; i < (v2 ? 4 : 2); ++i) head += char((len >> (8 * i)) & 0xFF);
    head += dict;

    write_atomically(path, [&](const std::string& temp) {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) throw FileError(path + ": cannot write: " + std::strerror(errno));
        out.write(head.data(), std::streamsize(head.size()));
        out.write(static_cast<const char*>(data), std::streamsize(bytes));
        out.close();
        if (!out) throw FileError(path + ": cannot write: " + std::strerror(errno));
    });
}

}  // namespace

size_t NpyHeader::element_count() const {
    size_t n = 1;
    for (size_t d : shape)
        if (__builtin_mul_overflow(n, d, &n)) return ~size_t(0);
    return n;
}

NpyFile::NpyFile(std::string path) : path_(std::move(path)) {
    check_regular_input(path_, ".npy file");
    in_.open(path_, std::ios::binary);
    if (!in_) throw FileError(path_ + ": cannot open: " + std::strerror(errno));
    NpyHeader& h = header_;
    unsigned char pre[12] = {};
    in_.read(reinterpret_cast<char*>(pre), 10);
    if (in_.gcount() < 10 || std::memcmp(pre, kMagic, kMagicSize) != 0)
        throw Error(path_ + ": not a .npy file (missing the \\x93NUMPY magic)");
    h.major = pre[6];
    h.minor = pre[7];
    if (h.major < 1 || h.major > 3 || h.minor != 0)
        throw Error(path_ + ": unsupported .npy format version " + std::to_string(h.major) + "." +
                    std::to_string(h.minor) + " (supported: 1.0, 2.0, 3.0)");
    size_t header_len = 0, prefix = 10;
    if (h.major == 1) {
        header_len = read_le(pre + 8, 2);
    } else {
        in_.read(reinterpret_cast<char*>(pre + 10), 2);
        if (in_.gcount() < 2) throw Error(path_ + ": truncated .npy header");
        header_len = read_le(pre + 8, 4);
        prefix = 12;
    }
    if (header_len > kMaxHeaderLen) throw Error(path_ + ": .npy header length " + std::to_string(header_len) + " is implausible");
    std::string text(header_len, '\0');
    in_.read(text.data(), std::streamsize(header_len));
    if (size_t(in_.gcount()) < header_len)
        throw Error(path_ + ": truncated .npy header (" + std::to_string(in_.gcount()) + " of " +
                    std::to_string(header_len) + " bytes)");
    h.data_offset = prefix + header_len;

    auto dict = HeaderParser(path_, text).parse_dict();
    for (const char* key : {"descr", "fortran_order", "shape"})
        if (!dict.count(key)) throw Error(path_ + ": .npy header has no '" + std::string(key) + "' key");
    for (const auto& [key, value] : dict)
        if (key != "descr" && key != "fortran_order" && key != "shape")
            throw Error(path_ + ": .npy header has an unexpected key '" + key + "'");

    const PyValue& descr = dict["descr"];
    if (descr.kind == PyValue::Str) {
        h.descr = descr.str;
    } else if (descr.kind == PyValue::List) {
        for (const PyValue& f : descr.items) {
            if (f.kind != PyValue::Tuple || f.items.size() != 2 || f.items[0].kind != PyValue::Str ||
                f.items[1].kind != PyValue::Str)
                throw Error(path_ + ": unsupported structured dtype (fields must be ('name', 'type') pairs)");
            h.fields.emplace_back(f.items[0].str, f.items[1].str);
        }
    } else {
        throw Error(path_ + ": .npy header 'descr' is neither a dtype string nor a list of fields");
    }

    const PyValue& fortran = dict["fortran_order"];
    if (fortran.kind != PyValue::Bool) throw Error(path_ + ": .npy header 'fortran_order' is not True or False");
    h.fortran_order = fortran.flag;
    if (h.fortran_order)
        throw Error(path_ + ": Fortran-ordered arrays are not supported (save with np.ascontiguousarray)");

    const PyValue& shape = dict["shape"];
    if (shape.kind != PyValue::Tuple) throw Error(path_ + ": .npy header 'shape' is not a tuple");
    for (const PyValue& d : shape.items) {
        if (d.kind != PyValue::Int || d.num < 0)
            throw Error(path_ + ": .npy header 'shape' must hold non-negative integers");
        h.shape.push_back(size_t(d.num));
    }
    if (h.element_count() == ~size_t(0)) throw Error(path_ + ": shape " + shape_repr(h.shape) + " is too large");
}

void NpyFile::check_data_size(size_t item_size) {
    const NpyHeader& h = header_;
    in_.seekg(0, std::ios::end);
    const auto file_size = static_cast<unsigned long long>(in_.tellg());
    const size_t count = h.element_count();
    size_t need = 0;
    if (__builtin_mul_overflow(count, item_size, &need))
        throw Error(path_ + ": shape " + shape_repr(h.shape) + " is too large");
    const unsigned long long have = file_size - h.data_offset;
    if (have < need)
        throw Error(path_ + ": truncated: shape " + shape_repr(h.shape) + " needs " + std::to_string(need) +
                    " bytes of data, the file has " + std::to_string(have));
    if (have > need)
        throw Error(path_ + ": " + std::to_string(have - need) + " unexpected bytes after the data of shape " +
                    shape_repr(h.shape));
    // A sparse file can announce gigabytes it does not hold: say so before allocating them.
    check_memory(need, path_ + ": the array of shape " + shape_repr(h.shape));
    in_.seekg(std::streamoff(h.data_offset));
}

void NpyFile::read_bytes(void* dst, size_t n) {
    if (!in_.read(static_cast<char*>(dst), std::streamsize(n))) throw Error(path_ + ": read error");
}

void NpyFile::require_matrix(size_t cols) const {
    if (header_.shape.size() != 2 || header_.shape[1] != cols)
        throw Error(path_ + ": array shape " + shape_repr(header_.shape) + " is not (N, " + std::to_string(cols) + ")");
}

NpyFloatArray NpyFile::read_float() {
    const NpyHeader& h = header_;
    const std::string what = h.fields.empty() ? "'" + h.descr + "'" : "structured " + descr_repr(h);
    size_t item = 0;
    if (h.descr == "<f4")
        item = 4;
    else if (h.descr == "<f8")
        item = 8;
    else if (h.descr == ">f4" || h.descr == ">f8")
        throw Error(path_ + ": big-endian dtype " + what + " is not supported (convert with .astype('<f4'))");
    else
        throw Error(path_ + ": dtype " + what + " is not supported (expected float32 '<f4' or float64 '<f8')");

    check_data_size(item);
    NpyFloatArray a;
    a.shape = h.shape;
    a.values.resize(h.element_count());
    if (item == 4) {
        read_bytes(a.values.data(), a.values.size() * 4);
    } else {
        std::vector<double> block(size_t(1) << 16);
        for (size_t done = 0; done < a.values.size();) {
            const size_t n = std::min(block.size(), a.values.size() - done);
            read_bytes(block.data(), n * 8);
            for (size_t i = 0; i < n; ++i) a.values[done + i] = float(block[i]);
            done += n;
        }
    }
    return a;
}

NpyFloatArray NpyFile::read_matrix(size_t cols) {
    require_matrix(cols);
    return read_float();
}

std::vector<double> NpyFile::read_matrix_double(size_t cols) {
    if (!holds_float64()) {
        const NpyFloatArray narrow = read_matrix(cols);  // '<f4', or refused with its reason
        return std::vector<double>(narrow.values.begin(), narrow.values.end());
    }
    require_matrix(cols);
    check_data_size(8);
    std::vector<double> values(header_.element_count());
    read_bytes(values.data(), values.size() * 8);
    return values;
}

std::vector<uint8_t> NpyFile::read_u8() {
    if (header_.descr != "|u1" && header_.descr != "|b1")
        throw Error(path_ + ": dtype " + descr_repr(header_) + " is not supported (expected uint8 '|u1' or bool '|b1')");
    if (header_.shape.size() != 1) throw Error(path_ + ": array shape " + shape_repr(header_.shape) + " is not (N,)");
    check_data_size(1);
    std::vector<uint8_t> values(header_.element_count());
    read_bytes(values.data(), values.size());
    return values;
}

std::vector<Hit> NpyFile::read_hits() {
    NpyHeader expected;
    expected.fields = {{"t", "<f4"}, {"prim", "<u4"}, {"u", "<f4"}, {"v", "<f4"}};
    if (header_.fields != expected.fields)
        throw Error(path_ + ": dtype " + descr_repr(header_) + " is not the hits dtype " + kNpyHitsDescr);
    if (header_.shape.size() != 1) throw Error(path_ + ": array shape " + shape_repr(header_.shape) + " is not (N,)");
    check_data_size(16);
    std::vector<Hit> hits(header_.element_count());
    std::vector<unsigned char> block(16 * 4096);
    for (size_t done = 0; done < hits.size();) {
        const size_t n = std::min<size_t>(4096, hits.size() - done);
        read_bytes(block.data(), n * 16);
        for (size_t i = 0; i < n; ++i) {
            Hit& hit = hits[done + i];
            const unsigned char* r = block.data() + 16 * i;
            std::memcpy(&hit.t, r, 4);
            std::memcpy(&hit.prim, r + 4, 4);
            std::memcpy(&hit.u, r + 8, 4);
            std::memcpy(&hit.v, r + 12, 4);
        }
        done += n;
    }
    return hits;
}

NpyHeader read_npy_header(const std::string& path) { return NpyFile(path).header(); }
NpyFloatArray read_npy_float(const std::string& path) { return NpyFile(path).read_float(); }
NpyFloatArray read_npy_matrix(const std::string& path, size_t cols) { return NpyFile(path).read_matrix(cols); }
std::vector<double> read_npy_matrix_double(const std::string& path, size_t cols) {
    return NpyFile(path).read_matrix_double(cols);
}
std::vector<uint8_t> read_npy_u8(const std::string& path) { return NpyFile(path).read_u8(); }
std::vector<Hit> read_npy_hits(const std::string& path) { return NpyFile(path).read_hits(); }

void write_npy_f32(const std::string& path, const std::vector<size_t>& shape, std::span<const float> values) {
    NpyHeader h;
    h.descr = "<f4";
    h.shape = shape;
    if (h.element_count() != values.size())
        throw Error(path + ": shape " + shape_repr(shape) + " does not match " + std::to_string(values.size()) + " values");
    write_array(path, h, values.data(), values.size_bytes());
}

void write_npy_u8(const std::string& path, std::span<const uint8_t> values) {
    NpyHeader h;
    h.descr = "|u1";
    h.shape = {values.size()};
    write_array(path, h, values.data(), values.size());
}

void write_npy_u32(const std::string& path, std::span<const uint32_t> values) {
    NpyHeader h;
    h.descr = "<u4";
    h.shape = {values.size()};
    write_array(path, h, values.data(), values.size_bytes());
}

void write_npy_records(const std::string& path, const std::vector<std::pair<std::string, std::string>>& fields,
                       size_t count, std::span<const unsigned char> records) {
    NpyHeader h;
    h.fields = fields;
    h.shape = {count};
    write_array(path, h, records.data(), records.size());
}

void write_npy_hits(const std::string& path, std::span<const Hit> hits) {
    NpyHeader h;
    h.fields = {{"t", "<f4"}, {"prim", "<u4"}, {"u", "<f4"}, {"v", "<f4"}};
    h.shape = {hits.size()};
    // Hit's member order (t, u, v, prim) differs from the file's record order: repack.
    std::vector<unsigned char> records(hits.size() * 16);
    for (size_t i = 0; i < hits.size(); ++i) {
        unsigned char* r = records.data() + 16 * i;
        std::memcpy(r, &hits[i].t, 4);
        std::memcpy(r + 4, &hits[i].prim, 4);
        std::memcpy(r + 8, &hits[i].u, 4);
        std::memcpy(r + 12, &hits[i].v, 4);
    }
    write_array(path, h, records.data(), records.size());
}

}  // namespace thicket
