// PLY loader tests: ASCII and both binary byte orders, odd layouts, corrupt files. Test files
// are written at run time into a fresh temporary directory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "loader_test_util.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::loader_ply_test {
namespace {

using namespace loader_test;

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

// Issue 16: bytes after the last element were accepted (the .npy and saved-structure readers
// refuse them): they mean the header does not describe the file.
TEST(LoaderPly, TrailingBytesAreRefused) {
    TempDir tmp;
    const std::string bin = simple_ply(Fmt::le), ascii = simple_ply(Fmt::ascii);
    EXPECT_NO_THROW(load_ply(tmp.file("ok.ply", ascii + "\n \n")));  // blank lines are not data
    const std::string extra_bin = tmp.file("extra.ply", bin + "junk");
    expect_error([&] { load_ply(extra_bin); }, extra_bin, {"4 bytes after the last element"});
    const std::string extra_ascii = tmp.file("extra_ascii.ply", ascii + "1 2 3\n");
    expect_error([&] { load_ply(extra_ascii); }, extra_ascii, {"data after the last element"});
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

}  // namespace
}  // namespace thicket::loader_ply_test
