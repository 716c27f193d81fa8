// Wavefront OBJ/MTL reader. Replaces tinyobjloader, which kept a face's vertex count in a byte
// (a 256-gon swallowed the faces after it), wrapped indices >= 2^32, read "v abc" as zeros and
// accepted arbitrary bytes: here every statement Thicket uses is checked, and anything that is
// not an OBJ statement is an error with its line number.
#include "obj_reader.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "thicket/core/error.h"
#include "thicket/scene/material_ranges.h"
#include "thicket/util/input_file.h"

namespace thicket::obj {

namespace {

/// Statements of the OBJ format that carry nothing Thicket uses: accepted and skipped.
constexpr std::string_view kSkipped[] = {
    "vt",   "vn",    "vp",     "l",   "p",    "g",    "o",         "s",        "mg",         "usemap",
    "maplib", "cstype", "deg", "bmat", "step", "curv", "curv2",    "surf",       "parm",       "trim",
    "hole", "scrv",  "sp",     "end", "con",  "ctech", "stech",    "bevel",      "c_interp",   "d_interp",
    "lod",  "shadow_obj", "trace_obj", "call", "csh"};

/// Splits text into lines (LF or CRLF; a trailing backslash joins the next line) and lines into
/// whitespace-separated tokens, counting lines for messages.
class Lines {
public:
    explicit Lines(std::string_view text) : text_(text) {}

    /// The next non-empty, non-comment line's tokens; false at the end.
    bool next(std::vector<std::string_view>& tokens) {
        tokens.clear();
        while (pos_ < text_.size()) {
            line_number_ = next_line_number_;
            size_t end = text_.find('\n', pos_);
            if (end == std::string_view::npos) end = text_.size();
            std::string_view line = text_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++next_line_number_;
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            tokenize(line, tokens);
            if (!tokens.empty() && tokens.back() == "\\") {  // continued on the next line
                tokens.pop_back();
                continue;
            }
            if (!tokens.empty() && tokens.front().front() == '#') tokens.clear();
            if (!tokens.empty()) return true;
        }
        return false;
    }
    size_t line() const { return line_number_; }

private:
    static void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
        size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
            size_t j = i;
            while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
            if (j > i) tokens.push_back(line.substr(i, j - i));
            i = j;
        }
    }

    std::string_view text_;
    size_t pos_ = 0;
    size_t line_number_ = 0, next_line_number_ = 1;
};

/// Text from the file, quoted, cut to `max` characters, unprintable bytes as '?': a message
/// about a binary file stays one readable line.
std::string shown(std::string_view s, size_t max = 40) {
    std::string out = "'";
    for (char c : s.substr(0, max)) out += (c >= 32 && c < 127) ? c : '?';
    return out + (s.size() > max ? "...'" : "'");
}

/// A decimal number as OBJ writes it (strtod syntax, a leading '+' allowed; "nan" and "inf" are
/// numbers too: such vertices are counted and warned about by the scene, not refused here).
bool parse_number(std::string_view s, double& out) {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    if (ec == std::errc::result_out_of_range) {  // beyond double: the vertex is infinite
        out = s.front() == '-' ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
        return end == s.data() + s.size();
    }
    return ec == std::errc() && end == s.data() + s.size();
}

bool parse_integer(std::string_view s, int64_t& out, bool& overflow) {
    overflow = false;
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    if (end != s.data() + s.size()) return false;
    overflow = ec == std::errc::result_out_of_range;
    return ec == std::errc() || overflow;
}

class ObjParser {
public:
    ObjParser(const std::string& path, bool materials) : path_(path), materials_(materials) {}

    ObjData parse(std::string_view text) {
        Lines lines(text);
        std::vector<std::string_view> t;
        while (lines.next(t)) {
            line_ = lines.line();
            const std::string_view key = t[0];
            if (key == "v")
                vertex(t);
            else if (key == "f" || key == "fo")
                face(t);
            else if (key == "usemtl")
                use_material(t);
            else if (key == "mtllib")
                material_library(t);
            else if (std::find(std::begin(kSkipped), std::end(kSkipped), key) == std::end(kSkipped))
                fail("unknown statement " + shown(key) + " (not an OBJ file?)");
        }
        // Positive indices may point forward (to vertices defined later): checked now.
        if (max_forward_.value > 0 && uint64_t(max_forward_.value) > out_.positions.size())
            throw Error(path_ + ": line " + std::to_string(max_forward_.line) + ": face " +
                        std::to_string(max_forward_.face) + ": vertex index " + std::to_string(max_forward_.value) +
                        " is out of range (" + std::to_string(out_.positions.size()) + " vertices)");
        return std::move(out_);
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw Error(path_ + ": line " + std::to_string(line_) + ": " + what);
    }

    void vertex(const std::vector<std::string_view>& t) {
        // x y z, then an optional w or r g b (vertex colours): only x y z are kept.
        if (t.size() < 4 || t.size() > 8)
            fail("a vertex needs x y z (and at most a w or r g b), got " + std::to_string(t.size() - 1) + " values");
        double c[7] = {};
        for (size_t i = 1; i < t.size(); ++i)
            if (!parse_number(t[i], c[i - 1])) fail("vertex coordinate " + shown(t[i]) + " is not a number");
        // Beyond float's range is infinite (a float vertex cannot hold it); the scene warns.
        out_.positions.push_back({float(c[0]), float(c[1]), float(c[2])});
    }

    void face(const std::vector<std::string_view>& t) {
        const size_t n = t.size() - 1;
        const size_t face_number = out_.face_sizes.size();
        if (n < 3) fail("face " + std::to_string(face_number) + " has " + std::to_string(n) + " vertices (at least 3)");
        if (n > std::numeric_limits<uint32_t>::max()) fail("face " + std::to_string(face_number) + " is too large");
        for (size_t k = 1; k <= n; ++k) {
            // v, v/vt, v//vn or v/vt/vn: only v is used; vt and vn must be integers if present.
            const std::string_view tok = t[k];
            const size_t slash = tok.find('/');
            const std::string_view v = tok.substr(0, slash);
            if (slash != std::string_view::npos) {
                std::string_view rest = tok.substr(slash + 1);
                const size_t slash2 = rest.find('/');
                const std::string_view vt = rest.substr(0, slash2);
                const std::string_view vn = slash2 == std::string_view::npos ? std::string_view() : rest.substr(slash2 + 1);
                int64_t ignored = 0;
                bool overflow = false;
                if ((!vt.empty() && !parse_integer(vt, ignored, overflow)) ||
                    (slash2 != std::string_view::npos && !parse_integer(vn, ignored, overflow)) ||
                    vn.find('/') != std::string_view::npos)
                    fail("face " + std::to_string(face_number) + ": " + shown(tok) + " is not a vertex reference (v, v/vt, v//vn or v/vt/vn)");
            }
            out_.indices.push_back(vertex_index(v, face_number));
        }
        out_.face_sizes.push_back(uint32_t(n));
        out_.face_materials.push_back(material_);
    }

    uint32_t vertex_index(std::string_view v, size_t face_number) {
        int64_t i = 0;
        bool overflow = false;
        const std::string where = "face " + std::to_string(face_number) + ": vertex index ";
        if (!parse_integer(v, i, overflow)) fail(where + shown(v) + " is not an integer");
        const size_t have = out_.positions.size();
        if (overflow) fail(where + std::string(v) + " is out of range (" + std::to_string(have) + " vertices)");
        if (i == 0) fail(where + "0 is invalid (OBJ indices count from 1; negative ones count back from the last vertex)");
        if (i < 0) {
            // Relative: -1 is the last vertex defined so far.
            if (uint64_t(-(i + 1)) >= have)
                fail(where + std::to_string(i) + " is relative and points before the first vertex (" +
                     std::to_string(have) + " defined so far)");
            return uint32_t(int64_t(have) + i);
        }
        if (uint64_t(i) > std::numeric_limits<uint32_t>::max())
            fail(where + std::to_string(i) + " is out of range (" + std::to_string(have) + " vertices)");
        if (uint64_t(i) > have && i > max_forward_.value) max_forward_ = {i, line_, face_number};
        return uint32_t(i - 1);
    }

    void use_material(const std::vector<std::string_view>& t) {
        if (t.size() < 2) fail("usemtl needs a material name");
        const std::string name(t[1]);
        const auto it = material_index_.find(name);
        if (it != material_index_.end()) {
            material_ = it->second;
            return;
        }
        material_ = -1;
        // Once a library has been read, an unknown name is worth a warning even when the library
        // held no materials at all (that was silent, hiding a wrong or empty .mtl).
        if (materials_ && (libraries_read_ > 0 || !out_.materials.empty()))
            out_.warnings.push_back("line " + std::to_string(line_) + ": usemtl " + shown(name) + ": no such material");
    }

    void material_library(const std::vector<std::string_view>& t) {
        if (t.size() < 2) fail("mtllib needs a file name");
        if (!materials_) return;
        const std::filesystem::path dir = std::filesystem::path(path_).parent_path();
        for (size_t k = 1; k < t.size(); ++k) {
            const std::string file = (dir / std::string(t[k])).string();
            std::error_code ec;
            if (!std::filesystem::exists(file, ec)) {
                out_.warnings.push_back("material library " + shown(file, 300) + " not found; materials are left out");
                continue;
            }
            const size_t first = out_.materials.size();
            try {
                parse_mtl(read_input_file(file, "material library"), file, out_.materials);
            } catch (const Error& e) {
                fail(std::string("mtllib: ") + e.what());
            }
            ++libraries_read_;
            if (out_.materials.size() == first)
                out_.warnings.push_back("material library " + shown(file, 300) + " has no materials (no newmtl)");
            for (size_t m = first; m < out_.materials.size(); ++m)
                material_index_.emplace(out_.materials[m].name, int32_t(m));
        }
    }

    const std::string& path_;
    const bool materials_;
    ObjData out_;
    size_t line_ = 0;
    int32_t material_ = -1;
    size_t libraries_read_ = 0;
    std::unordered_map<std::string, int32_t> material_index_;
    struct Forward {
        int64_t value = 0;
        size_t line = 0, face = 0;
    } max_forward_;
};

}  // namespace

ObjData parse_obj(std::string_view text, const std::string& path, bool materials) {
    return ObjParser(path, materials).parse(text);
}

ObjData read_obj(const std::string& path, bool materials) {
    const std::string text = read_input_file(path, "OBJ file");
    return parse_obj(text, path, materials);
}

void parse_mtl(std::string_view text, const std::string& path, std::vector<Material>& out) {
    Lines lines(text);
    std::vector<std::string_view> t;
    Material* current = nullptr;
    while (lines.next(t)) {
        const std::string where = path + ": line " + std::to_string(lines.line()) + ": ";
        const std::string_view key = t[0];
        if (key == "newmtl") {
            if (t.size() < 2) throw Error(where + "newmtl needs a name");
            out.emplace_back();
            current = &out.back();
            current->name = std::string(t[1]);
            continue;
        }
        // Colours, exponents, opacity and the illumination model Thicket keeps (the path tracer maps
        // them to its materials); every other statement (maps, Ka, Tf, ...) is skipped.
        const bool colour = key == "Kd" || key == "Ks" || key == "Ke";
        const bool scalar = key == "Ns" || key == "Ni" || key == "d" || key == "Tr" || key == "illum";
        if (!colour && !scalar) continue;
        if (!current) throw Error(where + std::string(key) + " before any newmtl");
        double v[3] = {};
        const size_t n = t.size() - 1;
        if (!(n == 1 || (colour && n == 3)))
            throw Error(where + std::string(key) + " takes " + (colour ? "1 or 3 numbers" : "1 number") + ", got " +
                        std::to_string(n) + " values");
        for (size_t i = 0; i < n; ++i)
            if (!parse_number(t[i + 1], v[i])) throw Error(where + std::string(key) + " value " + shown(t[i + 1]) + " is not a number");
        if (n == 1) v[1] = v[2] = v[0];
        // Every value against the shared table (material_ranges.h) before any conversion: a value
        // out of float's or int's range never reaches a cast.
        const MaterialParam param = key == "Kd"   ? MaterialParam::Diffuse
                                    : key == "Ks" ? MaterialParam::Specular
                                    : key == "Ke" ? MaterialParam::Emission
                                    : key == "Ns" ? MaterialParam::Shininess
                                    : key == "Ni" ? MaterialParam::Ior
                                    : key == "d"  ? MaterialParam::Dissolve
                                    : key == "Tr" ? MaterialParam::Transparency
                                                  : MaterialParam::Illum;
        for (size_t i = 0; i < n; ++i)
            if (const std::string why = material_value_problem(param, v[i]); !why.empty())
                throw Error(where + std::string(key) + (n == 1 ? "" : "[" + std::to_string(i) + "]") + ": " + why);
        const Vec3 c{float(v[0]), float(v[1]), float(v[2])};
        switch (param) {
            case MaterialParam::Diffuse: current->diffuse = c; break;
            case MaterialParam::Specular: current->specular = c; break;
            case MaterialParam::Emission: current->emission = c; break;
            case MaterialParam::Shininess: current->shininess = float(v[0]); break;
            case MaterialParam::Ior: current->ior = float(v[0]); break;
            case MaterialParam::Dissolve: current->dissolve = float(v[0]); break;
            case MaterialParam::Transparency: current->dissolve = float(1.0 - v[0]); break;  // Tr is 1 - d
            default: current->illum = int(v[0]); break;
        }
    }
}

}  // namespace thicket::obj
