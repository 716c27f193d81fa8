// Scene loader tests: PLY (ASCII and both binary byte orders, odd layouts, corrupt files), OBJ with
// materials, glTF/GLB with node transforms, load_scene dispatch, and the shared real scenes.
// Test files are written at run time into a fresh temporary directory.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket {
namespace {

namespace fs = std::filesystem;

/// A directory that exists for one test and is removed afterwards.
class TempDir {
public:
    TempDir() {
        static int counter = 0;
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() / ("thicket_loader_" + std::to_string(::getpid()) + "_" +
                                             std::to_string(counter++) + "_" + (info ? info->name() : "x"));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    std::string file(const std::string& name, const std::string& bytes) const {
        const fs::path p = path_ / name;
        std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return p.string();
    }
    std::string dir() const { return path_.string(); }

private:
    fs::path path_;
};

/// Expects an Error whose message names the file and contains every given fragment.
void expect_error(const std::function<void()>& load, const std::string& path,
                  const std::vector<std::string>& fragments) {
    try {
        load();
        ADD_FAILURE() << "no error for " << path;
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path, 0), 0u) << "message does not start with the path: " << what;
        for (const std::string& f : fragments)
            EXPECT_NE(what.find(f), std::string::npos) << f << " not in: " << what;
    }
}

// ---- a small PLY writer for any layout ---------------------------------------------------------

enum class Fmt { ascii, le, be };

struct PlyProp {
    std::string type, name;
    std::string count_type;  ///< non-empty: a list property
};
struct PlyElem {
    std::string name;
    std::vector<PlyProp> props;
    std::vector<std::vector<std::vector<double>>> rows;  ///< row -> property -> values
};

void put(std::string& out, const std::string& type, double v, Fmt fmt) {
    static const std::vector<std::string> names = {"char",   "int8",   "uchar", "uint8",   "short",  "int16",
                                                   "ushort", "uint16", "int",   "int32",   "uint",   "uint32",
                                                   "float",  "float32", "double", "float64"};
    const int kind = int(std::find(names.begin(), names.end(), type) - names.begin()) / 2;
    if (fmt == Fmt::ascii) {
        char buf[64];
        const char* pattern = kind == 6 ? "%.9g " : kind == 7 ? "%.17g " : "%.0f ";
        std::snprintf(buf, sizeof buf, pattern, v);
        out += buf;
        return;
    }
    unsigned char b[8];
    size_t n = 0;
    auto raw = [&](auto x) { n = sizeof x, std::memcpy(b, &x, n); };
    switch (kind) {
        case 0: raw(int8_t(v)); break;
        case 1: raw(uint8_t(v)); break;
        case 2: raw(int16_t(v)); break;
        case 3: raw(uint16_t(v)); break;
        case 4: raw(int32_t(v)); break;
        case 5: raw(uint32_t(v)); break;
        case 6: raw(float(v)); break;
        default: raw(double(v)); break;
    }
    if ((fmt == Fmt::be) == (std::endian::native == std::endian::little)) std::reverse(b, b + n);
    out.append(reinterpret_cast<const char*>(b), n);
}

std::string make_ply(Fmt fmt, const std::vector<PlyElem>& elems) {
    std::string out = "ply\nformat ";
    out += fmt == Fmt::ascii ? "ascii" : fmt == Fmt::le ? "binary_little_endian" : "binary_big_endian";
    out += " 1.0\ncomment written by loader_test\n";
    for (const PlyElem& e : elems) {
        out += "element " + e.name + " " + std::to_string(e.rows.size()) + "\n";
        for (const PlyProp& p : e.props)
            out += p.count_type.empty()
                       ? "property " + p.type + " " + p.name + "\n"
                       : "property list " + p.count_type + " " + p.type + " " + p.name + "\n";
    }
    out += "end_header\n";
    for (const PlyElem& e : elems)
        for (const auto& row : e.rows) {
            for (size_t i = 0; i < e.props.size(); ++i) {
                const PlyProp& p = e.props[i];
                if (!p.count_type.empty()) put(out, p.count_type, double(row[i].size()), fmt);
                for (double v : row[i]) put(out, p.type, v, fmt);
            }
            if (fmt == Fmt::ascii) out += "\n";
        }
    return out;
}

// The reference content: 6 vertices; a triangle, a quad and a pentagon.
const std::vector<Vec3> ref_positions = {{0.5f, -1.25f, 3.0f},  {1.75f, 0.0f, -2.5f}, {-0.125f, 8.0f, 1.0f},
                                         {3.25f, 3.5f, -0.75f}, {0.1f, 0.2f, 0.3f},   {-7.0f, 6.5f, 0.0625f}};
const std::vector<std::vector<double>> ref_faces = {{5, 0, 1}, {0, 1, 2, 3}, {4, 3, 5, 1, 0}};
const std::vector<uint32_t> ref_indices = {5, 0, 1, 0, 1, 2, 0, 2, 3, 4, 3, 5, 4, 5, 1, 4, 1, 0};

PlyElem simple_vertices(const std::string& type = "float") {
    PlyElem e{"vertex", {{type, "x", ""}, {type, "y", ""}, {type, "z", ""}}, {}};
    for (const Vec3& p : ref_positions) e.rows.push_back({{p.x}, {p.y}, {p.z}});
    return e;
}
PlyElem simple_faces(const std::string& count_type = "uchar", const std::string& type = "int",
                     const std::string& name = "vertex_indices") {
    PlyElem e{"face", {{type, name, count_type}}, {}};
    for (const auto& f : ref_faces) e.rows.push_back({f});
    return e;
}
std::string simple_ply(Fmt fmt) { return make_ply(fmt, {simple_vertices(), simple_faces()}); }

void expect_reference(const TriangleMesh& m) {
    EXPECT_EQ(m.positions, ref_positions);
    EXPECT_EQ(m.indices, ref_indices);
    EXPECT_EQ(m.triangle_count(), 6u);
}

// ---- PLY ---------------------------------------------------------------------------------------

TEST(LoaderPly, AsciiAndBothBinaryByteOrdersGiveIdenticalMeshes) {
    TempDir tmp;
    const TriangleMesh a = load_ply(tmp.file("a.ply", simple_ply(Fmt::ascii)));
    const TriangleMesh le = load_ply(tmp.file("le.ply", simple_ply(Fmt::le)));
    const TriangleMesh be = load_ply(tmp.file("be.ply", simple_ply(Fmt::be)));
    expect_reference(a);
    expect_reference(le);
    expect_reference(be);
    EXPECT_TRUE(a.material_ids.empty());
}

TEST(LoaderPly, PolygonsAreFanTriangulatedInOrder) {
    TempDir tmp;
    const TriangleMesh m = load_ply(tmp.file("fan.ply", simple_ply(Fmt::le)));
    ASSERT_EQ(m.triangle_count(), 6u);
    // Quad (0,1,2,3) -> (0,1,2), (0,2,3); pentagon (4,3,5,1,0) -> (4,3,5), (4,5,1), (4,1,0).
    EXPECT_EQ(m.vertex(1, 0), ref_positions[0]);
    EXPECT_EQ(m.vertex(2, 1), ref_positions[2]);
    EXPECT_EQ(m.vertex(5, 2), ref_positions[0]);
}

TEST(LoaderPly, UnusualTypesOrderAndExtraData) {
    // Double positions between normals and colours, face before vertex, an int16 list with a
    // ushort count named vertex_index, extra scalar and list properties, and extra elements.
    PlyElem vertex{"vertex",
                   {{"float", "nx", ""}, {"double", "z", ""}, {"uchar", "red", ""}, {"float64", "x", ""},
                    {"int", "tex", "uint8"}, {"double", "y", ""}, {"float32", "ny", ""}},
                   {}};
    for (const Vec3& p : ref_positions)
        vertex.rows.push_back({{0.5}, {p.z}, {200}, {p.x}, {1, 2, 3}, {p.y}, {-1}});
    PlyElem face{
        "face", {{"int", "flags", ""}, {"int16", "vertex_index", "ushort"}, {"float", "uv", "int"}}, {}};
    for (const auto& f : ref_faces) face.rows.push_back({{7}, f, {0.25, 0.5}});
    PlyElem edge{"edge", {{"int", "vertex1", ""}, {"int", "vertex2", ""}}, {{{0}, {1}}, {{2}, {3}}}};
    PlyElem extra{"material", {{"uchar", "name", "uint"}, {"double", "shine", ""}}, {{{65, 66}, {3.5}}}};
    PlyElem empty{"nothing", {}, {{}, {}}};
    TempDir tmp;
    for (Fmt fmt : {Fmt::ascii, Fmt::le, Fmt::be}) {
        SCOPED_TRACE(int(fmt));
        const std::string name = "odd" + std::to_string(int(fmt)) + ".ply";
        expect_reference(load_ply(tmp.file(name, make_ply(fmt, {edge, face, extra, vertex, empty}))));
    }
    // Every scalar type works as a coordinate and as an index type.
    for (const char* t : {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"}) {
        PlyElem v{"vertex",
                  {{t, "x", ""}, {t, "y", ""}, {t, "z", ""}},
                  {{{1}, {2}, {3}}, {{4}, {5}, {6}}, {{7}, {8}, {9}}}};
        PlyElem f{"face", {{t, "vertex_indices", "uint16"}}, {{{2, 1, 0}}}};
        for (Fmt fmt : {Fmt::ascii, Fmt::be}) {
            const TriangleMesh m = load_ply(tmp.file(std::string(t) + ".ply", make_ply(fmt, {v, f})));
            ASSERT_EQ(m.triangle_count(), 1u) << t;
            EXPECT_EQ(m.vertex(0, 0), Vec3(7, 8, 9)) << t;
        }
    }
}

TEST(LoaderPly, CrLfHeaderAndEmptyMesh) {
    TempDir tmp;
    std::string text = simple_ply(Fmt::ascii);
    std::string crlf;
    for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    expect_reference(load_ply(tmp.file("crlf.ply", crlf)));
    const TriangleMesh empty = load_ply(tmp.file(
        "empty.ply",
        make_ply(Fmt::le, {{"vertex", simple_vertices().props, {}}, {"face", simple_faces().props, {}}})));
    EXPECT_EQ(empty.triangle_count(), 0u);
}

TEST(LoaderPly, MalformedHeadersNameFileAndLine) {
    TempDir tmp;
    const std::string good = simple_ply(Fmt::ascii);
    auto variant = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    struct Case { std::string name, text; std::vector<std::string> fragments; };
    const std::vector<Case> cases = {
        {"noformat.ply", variant("format ascii 1.0\n", ""), {"no format line"}},
        {"badformat.ply",
         variant("format ascii", "format binary_middle_endian"),
         {"header line 2", "unknown format"}},
        {"badversion.ply", variant("ascii 1.0", "ascii 2.0"), {"header line 2", "version"}},
        {"badtype.ply", variant("property float x", "property flaot x"), {"header line 5", "flaot"}},
        {"badlisttype.ply", variant("list uchar", "list float"), {"header line 9", "count type"}},
        {"noend.ply", variant("end_header\n", ""), {"end_header"}},
        {"notply.ply", "plx\n" + good.substr(4), {"not a PLY file"}},
        {"badcount.ply", variant("element vertex 6", "element vertex six"), {"header line 4", "'six'"}},
        {"hugecount.ply",
         variant("element vertex 6", "element vertex 99999999999999999999"),
         {"header line 4"}},
        {"negcount.ply", variant("element vertex 6", "element vertex -6"), {"header line 4"}},
        {"orphanprop.ply", variant("comment written by loader_test", "property float w"), {"header line 3"}},
        {"junk.ply", variant("comment", "bogus"), {"header line 3", "bogus"}},
        {"noxyz.ply", variant("property float z", "property float w"), {"header line 4", "'z'"}},
        {"noindices.ply", variant("vertex_indices", "corners"), {"header line 8", "vertex_indices"}},
        {"noface.ply", variant("element face 3", "element polygon 3"), {"no 'element face'"}},
        {"twice.ply", variant("element face 3", "element vertex 3"), {"twice"}},
        {"empty.ply", "", {"not a PLY file"}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string path = tmp.file(c.name, c.text);
        expect_error([&] { load_ply(path); }, path, c.fragments);
    }
}

TEST(LoaderPly, BadBodiesAreErrorsNotCrashes) {
    TempDir tmp;
    const std::string bin = simple_ply(Fmt::le);
    const std::string truncated = tmp.file("trunc.ply", bin.substr(0, bin.size() - 5));
    expect_error([&] { load_ply(truncated); }, truncated, {"face", "end of file"});
    const std::string ascii = simple_ply(Fmt::ascii);
    const std::string truncated_ascii = tmp.file("trunc_ascii.ply", ascii.substr(0, ascii.size() - 8));
    expect_error([&] { load_ply(truncated_ascii); }, truncated_ascii, {"face", "end of file"});
    std::string bad_number = ascii;
    bad_number.replace(bad_number.find("-1.25"), 5, "-1.2x");
    const std::string bad_number_path = tmp.file("badnum.ply", bad_number);
    expect_error([&] { load_ply(bad_number_path); }, bad_number_path, {"1.2x", "vertex"});

    PlyElem faces = simple_faces();
    faces.rows[1][0][2] = 9;
    for (Fmt fmt : {Fmt::ascii, Fmt::le, Fmt::be}) {
        const std::string path =
            tmp.file("range" + std::to_string(int(fmt)) + ".ply", make_ply(fmt, {simple_vertices(), faces}));
        expect_error([&] { load_ply(path); }, path, {"face 1", "index 9", "out of range"});
    }
    faces = simple_faces();
    faces.rows[2][0] = {-1, 2, 3};
    const std::string negative = tmp.file("neg.ply", make_ply(Fmt::le, {simple_vertices(), faces}));
    expect_error([&] { load_ply(negative); }, negative, {"face 2", "index -1"});
    faces.rows[2][0] = {1, 2};
    for (Fmt fmt : {Fmt::ascii, Fmt::le}) {
        const std::string path =
            tmp.file("short" + std::to_string(int(fmt)) + ".ply", make_ply(fmt, {simple_vertices(), faces}));
        expect_error([&] { load_ply(path); }, path, {"face 2", "at least 3"});
    }
    const std::string dir = tmp.dir();
    EXPECT_THROW(load_ply(dir), Error);
    EXPECT_THROW(load_ply(tmp.dir() + "/absent.ply"), Error);
}

TEST(LoaderPly, AbsurdCountsDoNotAllocate) {
    TempDir tmp;
    for (Fmt fmt : {Fmt::ascii, Fmt::le, Fmt::be}) {
        std::string s = simple_ply(fmt);
        s.replace(s.find("element vertex 6"), 16, "element vertex 4000000000");
        const std::string path = tmp.file("absurd" + std::to_string(int(fmt)) + ".ply", s);
        expect_error([&] { load_ply(path); }, path, {"vertex"});
        s = simple_ply(fmt);
        s.replace(s.find("element face 3"), 14, "element face 3000000000");
        const std::string faces = tmp.file("absurdf" + std::to_string(int(fmt)) + ".ply", s);
        expect_error([&] { load_ply(faces); }, faces, {"face"});
    }
    // A uint list count of 4e9 in a tiny binary file.
    PlyElem faces{"face", {{"int", "vertex_indices", "uint"}}, {{{0, 1, 2}}}};
    std::string s = make_ply(Fmt::le, {simple_vertices(), faces});
    const uint32_t huge = 4000000000u;
    std::memcpy(&s[s.size() - 16], &huge, 4);
    const std::string path = tmp.file("biglist.ply", s);
    expect_error([&] { load_ply(path); }, path, {"face", "end of file"});
    // More vertices than 32-bit indices can address.
    const std::string many = tmp.file("many.ply",
                                      "ply\nformat ascii 1.0\nelement vertex 5000000000\n"
                                      "property float x\nproperty float y\nproperty float z\n"
                                      "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
    expect_error([&] { load_ply(many); }, many, {"too many vertices"});
}

TEST(LoaderPly, RandomCorruptionNeverCrashes) {
    TempDir tmp;
    std::mt19937 rng(12345);
    int n = 0;
    // A fresh name per file: rewriting one file in place makes ext4 flush on every close.
    auto try_load = [&](const std::string& bytes) {
        const std::string path = tmp.file("fuzz" + std::to_string(n++) + ".ply", bytes);
        try {
            const TriangleMesh m = load_ply(path);
            for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
        } catch (const Error&) {}
    };
    for (Fmt fmt : {Fmt::le, Fmt::be, Fmt::ascii}) {
        const std::string good = make_ply(fmt, {simple_vertices("double"), simple_faces("uint", "int")});
        for (size_t len = 0; len < good.size(); ++len) try_load(good.substr(0, len));
        for (int iter = 0; iter < 300; ++iter) {
            std::string s = good;
            const int flips = 1 + int(rng() % 4);
            for (int k = 0; k < flips; ++k) s[rng() % s.size()] = char(rng());
            try_load(s);
        }
    }
}

// ---- OBJ ---------------------------------------------------------------------------------------

const char* quad_obj =
    "mtllib quads.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\n"
    "f 1 2 3\n"                // before any usemtl: the default material
    "usemtl red\nf 1 2 3 4\n"  // quad
    "g second\nusemtl glow\nf 1/1 2/2 3/3 5/4 4/5\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 1\nvt 0 1\n";
const char* quad_mtl =
    "newmtl red\nKd 0.9 0.1 0.05\nKs 0.5 0.5 0.5\nNs 32\nNi 1.45\n"
    "newmtl glow\nKd 0.2 0.3 0.4\nKe 17 12 4\n";

TEST(LoaderObj, QuadsAndPentagonsWithMaterials) {
    TempDir tmp;
    tmp.file("quads.mtl", quad_mtl);
    const TriangleMesh m = load_obj(tmp.file("quads.obj", quad_obj));
    EXPECT_EQ(m.positions.size(), 5u);
    const std::vector<uint32_t> expected = {0, 1, 2, 0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 4, 0, 4, 3};
    EXPECT_EQ(m.indices, expected);
    ASSERT_EQ(m.materials.size(), 3u);
    EXPECT_EQ(m.materials[0].name, "red");
    EXPECT_EQ(m.materials[0].diffuse, Vec3(0.9f, 0.1f, 0.05f));
    EXPECT_EQ(m.materials[0].specular, Vec3(0.5f, 0.5f, 0.5f));
    EXPECT_FLOAT_EQ(m.materials[0].shininess, 32.0f);
    EXPECT_FLOAT_EQ(m.materials[0].ior, 1.45f);
    EXPECT_EQ(m.materials[1].name, "glow");
    EXPECT_EQ(m.materials[1].emission, Vec3(17, 12, 4));
    EXPECT_EQ(m.materials[2].name, "default");
    const std::vector<uint32_t> ids = {2, 0, 0, 1, 1, 1};
    EXPECT_EQ(m.material_ids, ids);
}

TEST(LoaderObj, MissingMtlIsOnlyAWarning) {
    TempDir tmp;
    const TriangleMesh m = load_obj(tmp.file("nomtl.obj", quad_obj));
    EXPECT_EQ(m.triangle_count(), 6u);
    EXPECT_TRUE(m.materials.empty());
    EXPECT_TRUE(m.material_ids.empty());
}

TEST(LoaderObj, ErrorsNameTheFile) {
    TempDir tmp;
    const std::string missing = tmp.dir() + "/missing.obj";
    expect_error([&] { load_obj(missing); }, missing, {});
    expect_error([&] { load_scene(missing); }, missing, {"no such file"});
    const std::string range = tmp.file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n");
    expect_error([&] { load_obj(range); }, range, {"face 1", "out of range"});
    const std::string relative = tmp.file("rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
    expect_error([&] { load_obj(relative); }, relative, {"face 0"});
    const std::string zero = tmp.file("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    expect_error([&] { load_obj(zero); }, zero, {});
}

// ---- glTF --------------------------------------------------------------------------------------

std::string base64(const std::string& bytes) {
    static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint8_t(bytes[i + 2]);
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? alphabet[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? alphabet[v & 63] : '=';
    }
    return out;
}

/// One triangle (indexed, ushort) plus 4 vertices used by a non-indexed strip and fan.
std::string gltf_buffer() {
    std::string b;
    auto f = [&](float v) { b.append(reinterpret_cast<const char*>(&v), 4); };
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) f(v);  // 0..36: triangle
    for (uint16_t i : {uint16_t(0), uint16_t(1), uint16_t(2), uint16_t(0)})
        b.append(reinterpret_cast<const char*>(&i), 2);
    // 44..92: quad corners
    for (float v : {0.f, 0.f, 5.f, 1.f, 0.f, 5.f, 0.f, 1.f, 5.f, 1.f, 1.f, 5.f}) f(v);
    return b;
}

std::string gltf_json(const std::string& buffer_uri, size_t length) {
    const std::string uri = buffer_uri.empty() ? "" : "\"uri\": \"" + buffer_uri + "\", ";
    return R"({"asset": {"version": "2.0"}, "scene": 0,
  "scenes": [{"nodes": [0, 2]}],
  "nodes": [{"translation": [10, 0, 0], "children": [1]},
            {"scale": [2, 2, 2], "mesh": 0},
            {"matrix": [0,1,0,0, -1,0,0,0, 0,0,1,0, 0,0,0,1], "mesh": 1}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
             {"primitives": [{"attributes": {"POSITION": 2}, "mode": 5},
                             {"attributes": {"POSITION": 2}, "mode": 6, "material": 1},
                             {"attributes": {"POSITION": 2}, "mode": 1}]}],
  "materials": [{"name": "orange", "pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1]},
                 "emissiveFactor": [2, 3, 4]},
                {"emissiveFactor": [1, 1, 1],
                 "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5}}}],
  "buffers": [{)" +
           uri + R"("byteLength": )" + std::to_string(length) + R"(}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 6},
                  {"buffer": 0, "byteOffset": 44, "byteLength": 48, "byteStride": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3"}]})";
}

std::string embedded_gltf() {
    const std::string b = gltf_buffer();
    return gltf_json("data:application/octet-stream;base64," + base64(b), b.size());
}

std::string make_glb(std::string json, std::string bin) {
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out;
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67u);
    u32(2);
    u32(uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    u32(uint32_t(json.size()));
    u32(0x4E4F534Au);
    out += json;
    u32(uint32_t(bin.size()));
    u32(0x004E4942u);
    out += bin;
    return out;
}

void expect_gltf_scene(const TriangleMesh& m) {
    ASSERT_EQ(m.triangle_count(), 5u);
    // Node 0 translates by (10,0,0); its child scales by 2: p -> 10 + 2p.
    EXPECT_EQ(m.vertex(0, 0), Vec3(10, 0, 0));
    EXPECT_EQ(m.vertex(0, 1), Vec3(12, 0, 0));
    EXPECT_EQ(m.vertex(0, 2), Vec3(10, 2, 0));
    // Node 2's matrix rotates 90 degrees about z: (x,y,z) -> (-y,x,z). Strip: (0,1,2), (1,3,2).
    EXPECT_EQ(m.vertex(1, 0), Vec3(0, 0, 5));
    EXPECT_EQ(m.vertex(1, 1), Vec3(0, 1, 5));
    EXPECT_EQ(m.vertex(2, 0), Vec3(0, 1, 5));
    EXPECT_EQ(m.vertex(2, 1), Vec3(-1, 1, 5));
    EXPECT_EQ(m.vertex(2, 2), Vec3(-1, 0, 5));
    // Fan: (0,1,2), (0,2,3).
    EXPECT_EQ(m.vertex(4, 0), Vec3(0, 0, 5));
    EXPECT_EQ(m.vertex(4, 2), Vec3(-1, 1, 5));
    ASSERT_EQ(m.materials.size(), 3u);
    EXPECT_EQ(m.materials[0].name, "orange");
    EXPECT_EQ(m.materials[0].diffuse, Vec3(1, 0.5f, 0.25f));
    EXPECT_EQ(m.materials[0].emission, Vec3(2, 3, 4));
    EXPECT_EQ(m.materials[1].emission, Vec3(5, 5, 5));
    EXPECT_EQ(m.materials[2].name, "default");
    const std::vector<uint32_t> ids = {0, 2, 2, 1, 1};
    EXPECT_EQ(m.material_ids, ids);
}

TEST(LoaderGltf, EmbeddedBufferWithNodeTransforms) {
    TempDir tmp;
    expect_gltf_scene(load_gltf(tmp.file("scene.gltf", embedded_gltf())));
}

TEST(LoaderGltf, ExternalBufferAndGlb) {
    TempDir tmp;
    tmp.file("scene.bin", gltf_buffer());
    expect_gltf_scene(load_gltf(tmp.file("external.gltf", gltf_json("scene.bin", gltf_buffer().size()))));
    const std::string glb = make_glb(gltf_json("", gltf_buffer().size()), gltf_buffer());
    expect_gltf_scene(load_gltf(tmp.file("scene.glb", glb)));
    expect_gltf_scene(load_scene(tmp.file("UPPER.GLB", glb)).mesh);
    for (size_t len = 0; len < glb.size(); len += 3) {  // truncated containers fail cleanly
        const std::string path = tmp.file("cut" + std::to_string(len) + ".glb", glb.substr(0, len));
        EXPECT_THROW(load_gltf(path), Error) << len;
    }
}

TEST(LoaderGltf, TrsRotationIsApplied) {
    TempDir tmp;
    std::string json = embedded_gltf();
    const std::string from = R"({"scale": [2, 2, 2], "mesh": 0})";
    // 90 degrees about z, then scale (2,1,1) applied first: (1,0,0) -> (2,0,0) -> (0,2,0).
    json.replace(json.find(from), from.size(),
                 R"({"scale": [2, 1, 1], "rotation": [0, 0, 0.70710678, 0.70710678], "mesh": 0})");
    const TriangleMesh m = load_gltf(tmp.file("trs.gltf", json));
    const Vec3 p = m.vertex(0, 1);
    EXPECT_NEAR(p.x, 10.0f, 1e-5f);
    EXPECT_NEAR(p.y, 2.0f, 1e-5f);
    EXPECT_NEAR(p.z, 0.0f, 1e-5f);
}

TEST(LoaderGltf, CorruptFilesAreErrors) {
    TempDir tmp;
    const std::string good = embedded_gltf();
    auto variant = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        const size_t at = s.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) s.replace(at, from.size(), to);
        return s;
    };
    struct Case { std::string name, text; std::vector<std::string> fragments; };
    const std::vector<Case> cases = {
        {"json.gltf", good.substr(0, good.size() / 2), {}},
        {"count.gltf",
         variant(R"("count": 3, "type": "VEC3")", R"("count": 300, "type": "VEC3")"),
         {"accessor 0"}},
        {"offset.gltf",
         variant(R"("byteOffset": 36, "byteLength": 6)", R"("byteOffset": 36, "byteLength": 600)"),
         {}},
        {"stride.gltf", variant(R"("byteStride": 12)", R"("byteStride": 8)"), {"byteStride"}},
        {"index.gltf",
         variant(R"("bufferView": 1, "componentType": 5123, "count": 3)",
                 R"("bufferView": 1, "componentType": 5123, "count": 3, "byteOffset": 2)"),
         {}},
        {"cycle.gltf",
         variant(R"("scale": [2, 2, 2], "mesh": 0)", R"("scale": [2, 2, 2], "mesh": 0, "children": [0])"),
         {"node 0"}},
        {"mesh.gltf", variant(R"("mesh": 1})", R"("mesh": 7})"), {"mesh 7"}},
        {"material.gltf", variant(R"("material": 0)", R"("material": 9)"), {"material 9"}},
        {"ctype.gltf",
         variant(R"("componentType": 5126, "count": 3)", R"("componentType": 5121, "count": 3)"),
         {"POSITION"}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string path = tmp.file(c.name, c.text);
        expect_error([&] { load_gltf(path); }, path, c.fragments);
    }
    // An index pointing past the vertices.
    std::string b = gltf_buffer();
    const uint16_t bad = 7;
    std::memcpy(&b[38], &bad, 2);
    const std::string range =
        tmp.file("range.gltf", gltf_json("data:application/octet-stream;base64," + base64(b), b.size()));
    expect_error([&] { load_gltf(range); }, range, {"index 7", "out of range"});
}

// ---- load_scene --------------------------------------------------------------------------------

TEST(LoaderScene, DispatchAndErrors) {
    TempDir tmp;
    const Scene s = load_scene(tmp.file("Mesh.PLY", simple_ply(Fmt::le)));
    EXPECT_EQ(s.name, tmp.dir() + "/Mesh.PLY");
    expect_reference(s.mesh);
    const std::string unknown = tmp.file("mesh.stl", "solid");
    expect_error([&] { load_scene(unknown); }, unknown, {".ply", ".obj", ".gltf", ".glb", "cornell"});
    const std::string none = tmp.file("mesh", "ply");
    expect_error([&] { load_scene(none); }, none, {"cornell"});
    expect_error([&] { load_scene(tmp.dir()); }, tmp.dir(), {"directory"});
    expect_error([&] { load_scene(tmp.dir() + "/nope.ply"); }, tmp.dir() + "/nope.ply", {"no such file"});
    EXPECT_STREQ(builtin_scene_names(), "cornell, teapot-patches");
    expect_error([&] { load_scene(none); }, none, {"teapot-patches"});
}

TEST(LoaderScene, CornellBuiltin) {
    const Scene s = load_scene("cornell");
    EXPECT_EQ(s.name, "cornell");
    EXPECT_EQ(s.primitive_count(), 36u);
    EXPECT_EQ(s.mesh.positions.size(), 72u);
    EXPECT_EQ(s.bounds().min, Vec3(-1.02f, 0.0f, -1.04f));
    EXPECT_EQ(s.bounds().max, Vec3(1.0f, 1.99f, 0.99f));
    ASSERT_EQ(s.mesh.material_ids.size(), 36u);
    const Material& light = s.mesh.materials[s.mesh.material_ids[35]];
    EXPECT_EQ(light.name, "light");
    EXPECT_GT(light.emission.x, 1.0f);
    EXPECT_EQ(s.mesh.materials[s.mesh.material_ids[0]].name, "floor");
    for (uint32_t t = 0; t < 36; ++t) EXPECT_GT(length(s.geometric_normal(t)), 0.0f) << t;
}

TEST(LoaderScene, FingerprintIsFnv1aOverVertexBits) {
    Scene s;
    s.mesh.positions = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
    s.mesh.indices = {0, 1, 2};
    uint64_t h = 0xcbf29ce484222325ull;
    auto bytes = [&](const void* p, size_t n) {
        for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 0x100000001b3ull;
    };
    for (const Vec3& v : s.mesh.positions) bytes(&v, 12);
    const uint64_t count = 1;
    bytes(&count, 8);
    EXPECT_EQ(s.fingerprint(), h);
    const uint64_t before = s.fingerprint();
    s.mesh.positions[2].z = 9.0000010f;
    EXPECT_NE(s.fingerprint(), before);
    EXPECT_EQ(load_scene("cornell").fingerprint(), load_scene("cornell").fingerprint());
}

// ---- shared real scenes ------------------------------------------------------------------------

bool shared_scenes_present() {
    std::error_code ec;
    return fs::is_directory(THICKET_SHARED_SCENES, ec);
}

TEST(LoaderShared, PlyCountsAndBoundsMatchReadme) {
    if (!shared_scenes_present()) GTEST_SKIP() << "../shared/scenes not found: " << THICKET_SHARED_SCENES;
    struct Row {
        const char* file;
        size_t tris, verts;
        Vec3 lo, hi;
    };
    const Row rows[] = {
        {"cornell-box.ply", 36, 72, {-1.02f, 0, -1.04f}, {1, 1.99f, 0.99f}},
        {"teapot.ply", 6320, 3644, {-3, 0, -2}, {3.434f, 3.15f, 2}},
        {"sponza-dabrovic.ply",
         66454,
         39999,
         {-17.4028f, -0.906689f, -7.79851f},
         {17.4172f, 15.6533f, 7.80149f}},
        {"bunny.ply",
         69451,
         34834,
         {-0.0946899f, 0.0329874f, -0.0618736f},
         {0.0610091f, 0.187321f, 0.0587997f}},
        {"sibenik.ply", 75284, 40979, {-20.1411f, -15.3123f, -8.4968f}, {20.1411f, 15.3f, 8.4968f}},
        {"dragon.ply",
         871414,
         437645,
         {-0.108324f, 0.0527295f, -0.0504143f},
         {0.0965662f, 0.197173f, 0.0412075f}},
    };
    for (const Row& r : rows) {
        SCOPED_TRACE(r.file);
        const Scene s = load_scene(std::string(THICKET_SHARED_SCENES) + "/" + r.file);
        EXPECT_EQ(s.primitive_count(), r.tris);
        EXPECT_EQ(s.mesh.positions.size(), r.verts);
        const Aabb b = s.bounds();
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(b.min[a], r.lo[a], 1e-3f) << a;
            EXPECT_NEAR(b.max[a], r.hi[a], 1e-3f) << a;
        }
    }
}

TEST(LoaderShared, CornellObjAndPlyMatchBuiltin) {
    if (!shared_scenes_present()) GTEST_SKIP() << "../shared/scenes not found: " << THICKET_SHARED_SCENES;
    const Scene builtin = load_scene("cornell");
    const Scene obj = load_scene(std::string(THICKET_SHARED_SCENES) + "/CornellBox-Original.obj");
    const Scene ply = load_scene(std::string(THICKET_SHARED_SCENES) + "/cornell-box.ply");
    ASSERT_EQ(obj.primitive_count(), 36u);
    ASSERT_EQ(ply.primitive_count(), 36u);
    for (uint32_t t = 0; t < 36; ++t)
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(obj.mesh.vertex(t, c), builtin.mesh.vertex(t, c)) << t << " " << c;
            EXPECT_EQ(ply.mesh.vertex(t, c), builtin.mesh.vertex(t, c)) << t << " " << c;
        }
    EXPECT_EQ(obj.mesh.positions, builtin.mesh.positions);
    EXPECT_EQ(obj.mesh.indices, builtin.mesh.indices);
    EXPECT_EQ(obj.fingerprint(), builtin.fingerprint());
    EXPECT_EQ(ply.fingerprint(), builtin.fingerprint());
}

}  // namespace
}  // namespace thicket
